// What the programs around statepack share besides a device: the project's rules for printing names
// that came from input, reading input files and writing outputs, and its thread pool. This is the code
// the packager and the dearchiver run themselves (dearchiver/support), behind a small public surface,
// so that the samples build against an installed package and keep the same rules.
#pragma once

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "statepack/result.hpp"

namespace statepack::bootstrap {

// `text` made safe for a terminal: control characters, C1 controls and bytes that are not well-formed
// UTF-8 become \xNN escapes (a hostile name cannot move the cursor or ring the bell); well-formed UTF-8
// passes unchanged.
std::string printable(std::string_view text);

// A whole regular file of at most `max_size` bytes. Directories, FIFOs, devices and sockets are refused
// without blocking; errors (`io_error`, also for a file over `max_size`) name the path and the reason.
Result<std::vector<uint8_t>> read_file(const std::filesystem::path& path, uint64_t max_size);

// Writes `bytes` to a temporary beside `path` and renames it over `path`: a failed write leaves the old
// file, a planted symlink is not followed, and none of `inputs` (compared as files, however spelled) is
// replaced (`invalid_argument`).
Result<void> write_file_atomically(const std::filesystem::path& path, std::span<const uint8_t> bytes,
                                   const std::vector<std::filesystem::path>& inputs = {});

// Why `path` may not be an output of a run that reads `inputs`: a symlink, a directory or another
// non-regular file, or one of the inputs however spelled (`..`, a symlink, a hard link). Empty when it
// may. A program checks its outputs with it before any work, so that a mistake costs nothing.
std::string output_refusal(const std::filesystem::path& path,
                           const std::vector<std::filesystem::path>& inputs = {});

// Runs work(i) for every i in [0, count) on up to `threads` threads (0: one per core), the calling
// thread included; returns when every call has returned.
void parallel_for(size_t count, uint32_t threads, const std::function<void(size_t)>& work);

}  // namespace statepack::bootstrap
