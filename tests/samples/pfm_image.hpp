// Reads the path tracer's PFM output (linear RGB floats) for the tests that measure it.
#pragma once

#include <gtest/gtest.h>

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

namespace statepack::testing {

struct PfmImage {
  uint32_t width = 0, height = 0;
  std::vector<float> rgb;  // rows top to bottom
  const float* at(uint32_t x, uint32_t y) const { return &rgb[(size_t(y) * width + x) * 3]; }
};

inline PfmImage read_pfm(const std::filesystem::path& path) {
  std::ifstream file(path, std::ios::binary);
  std::string magic;
  float scale = 0;
  PfmImage image;
  file >> magic >> image.width >> image.height >> scale;
  file.get();  // the single whitespace after the header
  EXPECT_EQ(magic, "PF") << path;
  EXPECT_LT(scale, 0.0f) << "little-endian PFM";
  image.rgb.resize(size_t(image.width) * image.height * 3);
  for (uint32_t y = image.height; y-- > 0;)  // PFM rows run bottom to top
    file.read(reinterpret_cast<char*>(&image.rgb[size_t(y) * image.width * 3]),
              std::streamsize(image.width * 3 * sizeof(float)));
  EXPECT_TRUE(file) << path;
  return image;
}

}  // namespace statepack::testing
