// Writing one compile-cache entry file, in a directory that other packs (and, on a shared file system,
// other machines) read and write at the same time.
#pragma once

#include <cstdint>
#include <filesystem>
#include <span>
#include <string>
#include <vector>

namespace statepack::packager {

// Writes `bytes` to a temporary beside `path` (".tmp-HOST-PID-N-...": unique across the machines sharing
// the directory, so no writer touches another's), then renames it over `path`: readers only ever see whole
// files, and a link planted at `path` is replaced, not followed. False with `error` set ("cannot write
// ...") when it could not; the temporary is removed then.
bool write_beside_and_rename(const std::filesystem::path& path, std::span<const uint8_t> bytes,
                             std::string& error);
// The same for a file made of `parts` one after another (an entry's header and its payload: not copied
// into one buffer first).
bool write_beside_and_rename(const std::filesystem::path& path, std::vector<std::span<const uint8_t>> parts,
                             std::string& error);

// Reads a whole entry file: a regular file of at most `max_bytes`, never reached through a link (one
// planted among the entries could point anywhere) and never waited on (O_NONBLOCK).
enum class EntryRead { ok, missing, unusable };
EntryRead read_entry_file(const std::filesystem::path& path, uint64_t max_bytes, std::vector<uint8_t>& out);

}  // namespace statepack::packager
