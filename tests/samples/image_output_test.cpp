// The sample writes finite images or fails: write_image refuses NaN, infinity and negative radiance with
// the pixel named,
// writes nothing then, and every image output is atomic and never follows a link.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <limits>
#include <vector>

#include "path_tracer/image_io.hpp"

namespace {

namespace fs = std::filesystem;

TEST(ImageOutput, NonFiniteImagesAreRefusedForEveryFormat) {
  const fs::path dir = fs::path(STATEPACK_TEST_OUTPUT_DIR) / "image_output";
  fs::remove_all(dir);
  fs::create_directories(dir);
  std::vector<float> rgba(4 * 3 * 2, 0.5f);
  for (float bad : {std::numeric_limits<float>::quiet_NaN(), std::numeric_limits<float>::infinity(),
                    -std::numeric_limits<float>::infinity()}) {
    rgba[(1 * 3 + 2) * 4 + 1] = bad;  // pixel (2, 1), green
    for (const char* name : {"a.png", "a.exr", "a.pfm"}) {
      std::string error = statepack::path_tracer::write_image(dir / name, rgba, 3, 2, 1.0f);
      EXPECT_EQ(error,
                "the render holds a non-finite value (NaN or infinity) at pixel (2, 1): no image written")
          << name;
      EXPECT_FALSE(fs::exists(dir / name)) << name;
    }
  }
  // Negative radiance (which no light of a checked scene gives) is refused the same way.
  rgba[(1 * 3 + 2) * 4 + 1] = -0.25f;
  for (const char* name : {"a.png", "a.exr", "a.pfm"}) {
    EXPECT_EQ(statepack::path_tracer::write_image(dir / name, rgba, 3, 2, 1.0f),
              "the render holds a negative radiance at pixel (2, 1): no image written")
        << name;
    EXPECT_FALSE(fs::exists(dir / name)) << name;
  }
  rgba[(1 * 3 + 2) * 4 + 1] = 0.25f;
  for (const char* name : {"a.png", "a.exr", "a.pfm"}) {
    EXPECT_EQ(statepack::path_tracer::write_image(dir / name, rgba, 3, 2, 1.0f), "") << name;
    EXPECT_GT(fs::file_size(dir / name), 20u) << name;
  }
  // Nothing but the images is left in the folder (no temporaries).
  size_t files = 0;
  for ([[maybe_unused]] const auto& entry : fs::directory_iterator(dir)) ++files;
  EXPECT_EQ(files, 3u);
}

}  // namespace
