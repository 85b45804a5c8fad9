// Whole-file reads and atomic writes, shared by the dearchiver (pipeline caches) and the packager.
#pragma once

#include <cstdint>
#include <filesystem>
#include <optional>
#include <span>
#include <string>
#include <vector>

namespace statepack {

// Writes `bytes` to a temporary file beside `path`, then renames it over `path`: a failed write never
// leaves a half file or destroys the previous one. Returns an empty string, or the reason.
std::string write_file_atomically(const std::filesystem::path& path, std::span<const uint8_t> bytes);

// The whole file, or nothing when it cannot be read.
std::optional<std::vector<uint8_t>> read_file(const std::filesystem::path& path);

}  // namespace statepack
