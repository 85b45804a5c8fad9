// statepack inspect: prints an archive's objects, sizes, layouts and bindings.
#pragma once

#include <iosfwd>
#include <string>

namespace statepack::packager {

// Returns an ExitCode: 0, kExitInputError for a damaged archive, kExitIoError when unreadable.
int run_inspect(const std::string& path, bool as_json, std::ostream& out, std::ostream& err);

}  // namespace statepack::packager
