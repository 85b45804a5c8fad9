#include "image_io.hpp"

#include <tinyexr.h>

#include <algorithm>
#include <cmath>
#include <cstring>

#include "file_io.hpp"

#define STB_IMAGE_WRITE_IMPLEMENTATION
#define STBI_WRITE_NO_STDIO
#include <stb/stb_image_write.h>

namespace statepack::path_tracer {
namespace {

uint8_t srgb_byte(float linear) {
  float c = std::clamp(linear, 0.0f, 1.0f);
  float s = c <= 0.0031308f ? 12.92f * c : 1.055f * std::pow(c, 1.0f / 2.4f) - 0.055f;
  return static_cast<uint8_t>(std::lround(s * 255.0f));
}

std::span<const uint8_t> as_bytes(const std::vector<uint8_t>& v) {
  return {v.data(), v.size()};
}

}  // namespace

std::string write_png_rgb8(const std::filesystem::path& path, const std::vector<uint8_t>& rgb, uint32_t width,
                           uint32_t height) {
  std::vector<uint8_t> file;
  stbi_write_png_to_func(
      [](void* out, void* data, int size) {
        auto* bytes = static_cast<uint8_t*>(data);
        auto* vec = static_cast<std::vector<uint8_t>*>(out);
        vec->insert(vec->end(), bytes, bytes + size);
      },
      &file, int(width), int(height), 3, rgb.data(), int(width * 3));
  if (file.empty()) return "PNG encoding failed";
  return write_file_atomically(path, as_bytes(file));
}

std::string write_image(const std::filesystem::path& path, const std::vector<float>& rgba, uint32_t width,
                        uint32_t height, float exposure) {
  const std::string ext = path.extension().string();
  const size_t pixels = size_t(width) * height;
  std::vector<uint8_t> file;
  if (ext == ".png") {
    std::vector<uint8_t> rgb(pixels * 3);
    for (size_t i = 0; i < pixels; ++i)
      for (int c = 0; c < 3; ++c) rgb[i * 3 + c] = srgb_byte(rgba[i * 4 + c] * exposure);
    return write_png_rgb8(path, rgb, width, height);
  } else if (ext == ".pfm") {
    // Portable float map: "PF", size, negative scale = little-endian, rows bottom to top.
    std::string header = "PF\n" + std::to_string(width) + " " + std::to_string(height) + "\n-1.0\n";
    file.assign(header.begin(), header.end());
    for (uint32_t y = height; y-- > 0;)
      for (uint32_t x = 0; x < width; ++x)
        for (int c = 0; c < 3; ++c) {
          float v = rgba[(size_t(y) * width + x) * 4 + c];
          uint8_t b[4];
          std::memcpy(b, &v, 4);
          file.insert(file.end(), b, b + 4);
        }
  } else if (ext == ".exr") {
    std::vector<float> rgb(pixels * 3);
    for (size_t i = 0; i < pixels; ++i)
      for (int c = 0; c < 3; ++c) rgb[i * 3 + c] = rgba[i * 4 + c];
    // tinyexr writes the file itself; write beside the target, then rename (atomic like the rest).
    std::filesystem::path temp = path;
    temp += ".tmp-exr";
    const char* err = nullptr;
    if (SaveEXR(rgb.data(), int(width), int(height), 3, /*save_as_fp16=*/0, temp.c_str(), &err) !=
        TINYEXR_SUCCESS) {
      std::string reason = err ? err : "unknown";
      FreeEXRErrorMessage(err);
      return "EXR encoding failed: " + reason;
    }
    std::error_code ec;
    std::filesystem::rename(temp, path, ec);
    return ec ? "cannot write '" + path.string() + "': " + ec.message() : "";
  } else {
    return "unknown image type '" + ext + "' (use .png, .exr or .pfm)";
  }
  return write_file_atomically(path, as_bytes(file));
}

}  // namespace statepack::path_tracer
