// Independent renders (seeds) in this process, and the per-pixel test of their mean against the CPU
// reference. A low-discrepancy sampler's samples are not independent, so the error of a pixel's mean
// is estimated from independent scramblings (seeds), and the critical value is Student's t with
// (seeds - 1) degrees of freedom, Sidak-corrected over all pixel channels.
#pragma once

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "path_tracer/app.hpp"
#include "path_tracer/offline.hpp"
#include "path_tracer/reference.hpp"
#include "seed_statistics.hpp"

namespace statepack::testing {

// `seeds` independent renders of `spp` samples each (RGBA rows, top to bottom).
inline std::vector<std::vector<float>> render_seeds(const path_tracer::Scene& scene,
                                                    path_tracer::RenderSettings settings, uint32_t width,
                                                    uint32_t height, uint32_t spp, uint32_t seeds) {
  std::vector<std::vector<float>> images;
  auto vk = bootstrap::VulkanContext::create({});
  EXPECT_TRUE(vk) << vk.error().message;
  if (!vk) return images;
  {
    auto dearchiver = path_tracer::load_archive(**vk, STATEPACK_PATH_TRACER_ARCHIVE);
    EXPECT_TRUE(dearchiver);
    if (!dearchiver) return images;
    settings.samples_per_frame = 32;
    for (uint32_t s = 1; s <= seeds; ++s) {
      settings.seed = s * 7919u;
      auto rendered = path_tracer::render_offline(**vk, *dearchiver, scene, settings, width, height, spp);
      EXPECT_TRUE(rendered) << rendered.error().message;
      if (!rendered) return images;
      images.push_back(std::move(rendered->rgba));
    }
  }
  (*vk)->destroy_device();
  EXPECT_EQ(path_tracer::report_validation(**vk), 0u) << "validation messages";
  return images;
}

// The fraction of pixel channels whose mean over the seeds passes the t-test against the reference.
// Float's rounding of an (almost) exact pixel value, as a standard error: a pixel lit only by a light
// without area has next to no variance, so rounding alone would otherwise fail its z- or t-test.
inline double float_rounding(double value) {
  return 2e-6 * std::abs(value);
}

inline double pass_rate(const std::string& name, const std::vector<std::vector<float>>& images,
                        const path_tracer::ReferenceImage& reference) {
  const size_t pixels = size_t(reference.width) * reference.height, tests = pixels * 3;
  const double critical = sidak_t(0.01, tests, double(images.size()) - 1);
  size_t failed = 0, not_finite = 0;
  double worst = 0;
  for (size_t p = 0; p < pixels; ++p)
    for (int c = 0; c < 3; ++c) {
      std::vector<double> values;
      for (const auto& image : images) {
        values.push_back(image[p * 4 + c]);
        not_finite += !std::isfinite(image[p * 4 + c]);
      }
      auto [mean, variance] = mean_and_variance_of_mean(values);
      const double ref = reference.mean[p * 3 + c];
      const double rounding = float_rounding(ref);
      const double sigma =
          std::sqrt(variance + reference.variance[p * 3 + c] / reference.samples + rounding * rounding);
      const double t = sigma > 0 ? std::abs(mean - ref) / sigma : (std::abs(mean - ref) < 1e-4 ? 0 : 1e9);
      worst = std::max(worst, std::min(t, 1e3));
      failed += t > critical;
    }
  EXPECT_EQ(not_finite, 0u) << name;
  const double rate = 1.0 - double(failed) / double(tests);
  std::printf("%s: %.3f %% of %zu pixel channels pass |t| < %.2f (worst %.1f)\n", name.c_str(), 100 * rate,
              tests, critical, worst);
  return rate;
}

}  // namespace statepack::testing
