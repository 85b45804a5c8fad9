// Whole-file reads and atomic writes, shared by the dearchiver (archives, pipeline caches) and the
// packager.
#pragma once

#include <cstdint>
#include <filesystem>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "statepack/result.hpp"

namespace statepack::detail {

// Writes `bytes` to a temporary beside `path`, then renames it over `path`: a failed write never leaves a
// half file or destroys the previous one, and no planted link is followed (see output_files.hpp; this is
// an OutputSet of one file). `inputs` are files the output must not replace (compared by identity).
// `invalid_argument` when the path may not be an output (OutputSet::refuse_reason), `io_error` when
// writing fails; the message names the path and the reason.
Result<void> write_file_atomically(const std::filesystem::path& path, std::span<const uint8_t> bytes,
                                   const std::vector<std::filesystem::path>& inputs = {});

// The same for the library's own save functions (save_pipeline_cache, Dearchiver::save_variants), whose
// contract is `io_error` for any file that cannot be written: a path that may not be an output (a
// directory, a device, a symlink) is that too, not an `invalid_argument`.
Result<void> save_file_atomically(const std::filesystem::path& path, std::span<const uint8_t> bytes);

// Which file a path reached (device and inode): the same file however the path is spelled (`..`, a
// symlink, a hard link), so outputs can refuse to replace an input.
struct FileIdentity {
  uint64_t device = 0, inode = 0;
  auto operator<=>(const FileIdentity&) const = default;
};

// A whole file in 4-byte aligned storage (SPIR-V inside archives is handed to Vulkan in place).
struct FileBytes {
  std::vector<uint32_t> words;
  size_t size = 0;
  FileIdentity identity;
  std::span<const uint8_t> bytes() const { return {reinterpret_cast<const uint8_t*>(words.data()), size}; }
};

// "a directory", "a FIFO", "a character device", ... for messages about a file's type (st_mode).
const char* file_kind(unsigned mode);

// Reads a regular file of at most `max_size` bytes. Directories, FIFOs, devices and sockets are
// refused without blocking (the file is opened with O_NONBLOCK and checked with fstat before any
// read); errors name the path and the operating system's reason. Throws only std::bad_alloc.
// The identity of the file `path` reaches (following links), if it exists.
std::optional<FileIdentity> file_identity(const std::filesystem::path& path);

// Messages name the file `display` (default: the path); `size_hint` follows the message for a file
// over `max_size` (the packager says how to raise its limit).
Result<FileBytes> read_regular_file(const std::filesystem::path& path, uint64_t max_size,
                                    const std::string& display = {}, std::string_view size_hint = {});

}  // namespace statepack::detail
