// statepack inspect: prints an archive's objects, sizes, layouts and bindings.
#pragma once

#include <iosfwd>
#include <string>

#include "format/archive_format.hpp"

namespace statepack::packager {

// Returns an ExitCode: 0, kExitInputError for a damaged archive, kExitIoError when unreadable.
int run_inspect(const std::string& path, bool as_json, std::ostream& out, std::ostream& err);

// What `inspect` prints, for decoded contents of an archive of `size` bytes (also --print_contents).
void print_archive(const format::Contents& contents, size_t size, bool as_json, std::ostream& out);

}  // namespace statepack::packager
