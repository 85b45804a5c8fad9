// Loading an archive whole: decoded, its shaders checked against its layouts, its content version
// compared. The dearchiver's Archive is a thin owner of this; statepack's own tools (inspect, merge) and
// tests load archives with it directly, so none of them needs the Vulkan runtime for it.
#pragma once

#include <cstdint>
#include <filesystem>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "archive_format.hpp"
#include "spirv_walk.hpp"

namespace statepack::format {

// A decoded archive and, when it was read from a file, the bytes its `contents.spirv` spans point into.
// Moving it keeps the spans valid (a vector's buffer moves with it).
struct LoadedArchive {
  std::vector<uint32_t> owned;  // uint32_t storage keeps file bytes 4-byte aligned for SPIR-V
  Contents contents;
  std::vector<spirv::Module> modules;  // each blob walked by the load's checks, kept for the runtime
};

// Decodes and checks caller-owned bytes (4-byte aligned; they must outlive the result's spans).
// `origin` starts every error message (a file name, or "archive in memory"). `threads`: the SPIR-V is
// walked on that many (0: every core); the runtime walks on the calling thread, the packer on its -t.
// `walked`, when given, receives the walk of every blob (check_shader_interfaces).
Result<Contents> load_archive(std::span<const uint8_t> bytes,
                              std::optional<uint32_t> required_content_version, const std::string& origin,
                              uint32_t threads = 1, std::vector<spirv::Module>* walked = nullptr);

// The OpenGL block checked as load_archive checks the rest: its records (validate_gl), then against its
// SPIR-V (check_gl_shader_interfaces). The Vulkan runtime leaves it out (it never reads that block, and
// a Vulkan-only program links none of it); statepack_gl runs it in add_archive, and the packager's
// tools on every archive they load. `origin` starts the error message.
Result<void> check_opengl(const Contents& contents, const std::string& origin);

// Reads a regular file (at most 4 GiB: record offsets are 32-bit) and loads it; errors name the file.
Result<LoadedArchive> load_archive_file(const std::filesystem::path& path,
                                        std::optional<uint32_t> required_content_version = std::nullopt);

// The whole archive, its OpenGL block included (load_archive or load_archive_file, then check_opengl):
// how statepack's own tools read an archive.
Result<Contents> load_archive_with_opengl(std::span<const uint8_t> bytes,
                                          std::optional<uint32_t> required_content_version,
                                          const std::string& origin, uint32_t threads = 1);
Result<LoadedArchive> load_archive_file_with_opengl(const std::filesystem::path& path);

}  // namespace statepack::format
