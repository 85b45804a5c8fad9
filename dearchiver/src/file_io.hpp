// Whole-file reads and atomic writes, shared by the dearchiver (archives, pipeline caches) and the
// packager.
#pragma once

#include <cstdint>
#include <filesystem>
#include <span>
#include <string>
#include <vector>

#include "statepack/result.hpp"

namespace statepack {

// Writes `bytes` to a temporary file beside `path`, then renames it over `path`: a failed write never
// leaves a half file or destroys the previous one. Returns an empty string, or the reason.
std::string write_file_atomically(const std::filesystem::path& path, std::span<const uint8_t> bytes);

// A whole file in 4-byte aligned storage (SPIR-V inside archives is handed to Vulkan in place).
struct FileBytes {
  std::vector<uint32_t> words;
  size_t size = 0;
  std::span<const uint8_t> bytes() const { return {reinterpret_cast<const uint8_t*>(words.data()), size}; }
};

// Reads a regular file of at most `max_size` bytes. Directories, FIFOs, devices and sockets are
// refused without blocking (the file is opened with O_NONBLOCK and checked with fstat before any
// read); errors name the path and the operating system's reason. Throws only std::bad_alloc.
Result<FileBytes> read_regular_file(const std::filesystem::path& path, uint64_t max_size);

}  // namespace statepack
