// Writing rendered images: PNG (tone-mapped sRGB, 8-bit), EXR and PFM (linear float radiance).
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

namespace statepack::path_tracer {

// `rgba` is linear radiance, RGBA32F, rows top to bottom. Returns an empty string or the reason.
// The format follows the extension: .png (clamped, sRGB-encoded after `exposure`), .exr, .pfm. An image
// holding NaN or infinity is refused (a render that diverged is an error, not a picture), and so is an
// output path that is one of `inputs`, a link or a non-regular file.
std::string write_image(const std::filesystem::path& path, const std::vector<float>& rgba, uint32_t width,
                        uint32_t height, float exposure,
                        const std::vector<std::filesystem::path>& inputs = {});

// 8-bit RGB (already display-encoded) as PNG. Returns an empty string or the reason.
std::string write_png_rgb8(const std::filesystem::path& path, const std::vector<uint8_t>& rgb, uint32_t width,
                           uint32_t height, const std::vector<std::filesystem::path>& inputs = {});

}  // namespace statepack::path_tracer
