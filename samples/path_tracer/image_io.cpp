#include "image_io.hpp"

#include <tinyexr.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <cstring>

#include "statepack/bootstrap/host_tools.hpp"

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
                           uint32_t height, const std::vector<std::filesystem::path>& inputs) {
  std::vector<uint8_t> file;
  stbi_write_png_to_func(
      [](void* out, void* data, int size) {
        auto* bytes = static_cast<uint8_t*>(data);
        auto* vec = static_cast<std::vector<uint8_t>*>(out);
        vec->insert(vec->end(), bytes, bytes + size);
      },
      &file, int(width), int(height), 3, rgb.data(), int(width * 3));
  if (file.empty()) return "PNG encoding failed";
  auto written = bootstrap::write_file_atomically(path, as_bytes(file), inputs);
  return written ? std::string() : written.error().message;
}

std::string write_image(const std::filesystem::path& path, const std::vector<float>& rgba, uint32_t width,
                        uint32_t height, float exposure, const std::vector<std::filesystem::path>& inputs) {
  const std::string ext = path.extension().string();
  const size_t pixels = size_t(width) * height;
  if (rgba.size() < pixels * 4) return "the image has fewer pixels than its size says";
  for (size_t i = 0; i < pixels * 4; ++i) {
    const bool finite = std::isfinite(rgba[i]), negative = i % 4 != 3 && rgba[i] < 0;  // alpha is no radiance
    if (finite && !negative) continue;
    return std::string(finite ? "the render holds a negative radiance"
                              : "the render holds a non-finite value (NaN or infinity)") +
           " at pixel (" + std::to_string(i / 4 % width) + ", " + std::to_string(i / 4 / width) +
           "): no image written";
  }
  std::vector<uint8_t> file;
  if (ext == ".png") {
    std::vector<uint8_t> rgb(pixels * 3);
    for (size_t i = 0; i < pixels; ++i)
      for (int c = 0; c < 3; ++c) rgb[i * 3 + c] = srgb_byte(rgba[i * 4 + c] * exposure);
    return write_png_rgb8(path, rgb, width, height, inputs);
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
    // Encoded in memory (tinyexr's file writer would follow a link planted at its path), then written
    // like every other output: atomically, never through a link.
    std::vector<float> planes[3];  // EXR viewers expect B, G, R channel order
    for (int ch = 0; ch < 3; ++ch) {
      planes[ch].resize(pixels);
      for (size_t i = 0; i < pixels; ++i) planes[ch][i] = rgba[i * 4 + size_t(2 - ch)];
    }
    float* plane_pointers[3] = {planes[0].data(), planes[1].data(), planes[2].data()};
    EXRImage image;
    InitEXRImage(&image);
    image.num_channels = 3;
    image.images = reinterpret_cast<unsigned char**>(plane_pointers);
    image.width = int(width);
    image.height = int(height);
    EXRHeader header;
    InitEXRHeader(&header);
    header.compression_type =
        width < 16 && height < 16 ? TINYEXR_COMPRESSIONTYPE_NONE : TINYEXR_COMPRESSIONTYPE_ZIP;
    EXRChannelInfo channels[3] = {};
    int pixel_types[3] = {TINYEXR_PIXELTYPE_FLOAT, TINYEXR_PIXELTYPE_FLOAT, TINYEXR_PIXELTYPE_FLOAT};
    const char* names[3] = {"B", "G", "R"};
    for (int ch = 0; ch < 3; ++ch) std::memcpy(channels[ch].name, names[ch], 2);
    header.num_channels = 3;
    header.channels = channels;
    header.pixel_types = pixel_types;
    header.requested_pixel_types = pixel_types;
    unsigned char* memory = nullptr;
    const char* err = nullptr;
    size_t size = SaveEXRImageToMemory(&image, &header, &memory, &err);
    if (size == 0) {
      std::string reason = err ? err : "unknown";
      FreeEXRErrorMessage(err);
      return "EXR encoding failed: " + reason;
    }
    file.assign(memory, memory + size);
    std::free(memory);
  } else {
    return "unknown image type '" + ext + "' (use .png, .exr or .pfm)";
  }
  auto written = bootstrap::write_file_atomically(path, as_bytes(file), inputs);
  return written ? std::string() : written.error().message;
}

}  // namespace statepack::path_tracer
