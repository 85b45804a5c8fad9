// Every estimator variant (sampler, and the estimators beside them) against the double-precision CPU
// reference of the same integral, per pixel. A low-discrepancy sampler's samples are not independent,
// so the error of a pixel's mean is estimated from independent scramblings (seeds), and the critical
// value is Student's t with (seeds - 1) degrees of freedom, Sidak-corrected over all pixel channels.
// Rendering happens in this process (one Vulkan device, validation on, any message fails).
#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>
#include <string>

#include "path_tracer/app.hpp"
#include "path_tracer/offline.hpp"
#include "path_tracer/reference.hpp"
#include "seed_renders.hpp"

namespace {

using namespace statepack;
using namespace statepack::path_tracer;
using statepack::testing::mean_and_variance_of_mean;
using statepack::testing::pass_rate;
using statepack::testing::render_seeds;

struct Variant {
  std::string name;
  RenderSettings settings;
};

// Next-event estimation with each sampler and each way of sampling the light, with and without Russian
// roulette (from the first bounce, so that it plays at 3 bounces as well).
std::vector<Variant> nee_variants() {
  std::vector<Variant> out;
  for (Sampler sampler : {Sampler::sobol, Sampler::random})
    for (LightSampling light : {LightSampling::solid_angle, LightSampling::area})
      for (uint32_t roulette : {0u, 1u}) {
        Variant v{std::string("nee ") + (sampler == Sampler::sobol ? "sobol" : "random") +
                      (light == LightSampling::area ? " area" : " solid-angle") +
                      (roulette ? " roulette" : ""),
                  {}};
        v.settings.sampler = sampler;
        v.settings.light_sampling = light;
        v.settings.roulette_start = roulette;
        out.push_back(v);
      }
  return out;
}

TEST(EstimatorVariants, EveryNeeVariantMatchesTheCpuReferencePerPixel) {
  auto scene = load_scene(STATEPACK_DEFAULT_SCENE);
  ASSERT_TRUE(scene);
  for (uint32_t bounces : {3u, 8u}) {
    RenderSettings reference_settings;
    reference_settings.bounces = bounces;
    reference_settings.seed = 1000;
    const ReferenceImage reference = render_reference(*scene, reference_settings, 48, 36, 1024);
    for (const Variant& v : nee_variants()) {
      RenderSettings s = v.settings;
      s.bounces = bounces;
      const std::string name = v.name + ", " + std::to_string(bounces) + " bounces";
      EXPECT_GE(pass_rate(name, render_seeds(*scene, s, 48, 36, 64, 16), reference), 0.9975) << name;
    }
  }
}

// Image means of independent seeds: mean and variance of the mean.
std::pair<double, double> image_mean_over_seeds(const std::vector<std::vector<float>>& images) {
  std::vector<double> means;
  for (const auto& image : images) {
    double sum = 0;
    for (size_t i = 0; i < image.size(); i += 4) sum += image[i] + image[i + 1] + image[i + 2];
    means.push_back(sum / double(image.size() / 4 * 3));
  }
  return mean_and_variance_of_mean(means);
}

// Russian roulette leaves the expectation unchanged: the image mean with roulette from the first bounce
// equals the mean without, within 4 standard errors estimated from independent seeds (the samples of
// one scrambled sequence are not independent), at 8 bounces, for both samplers.
TEST(RussianRoulette, ImageMeanIsUnchanged) {
  auto scene = load_scene(STATEPACK_DEFAULT_SCENE);
  ASSERT_TRUE(scene);
  for (Sampler sampler : {Sampler::sobol, Sampler::random}) {
    RenderSettings s;
    s.bounces = 8;
    s.sampler = sampler;
    s.roulette_start = 0;
    auto [m_off, v_off] = image_mean_over_seeds(render_seeds(*scene, s, 32, 24, 256, 8));
    s.roulette_start = 1;
    auto [m_on, v_on] = image_mean_over_seeds(render_seeds(*scene, s, 32, 24, 256, 8));
    const double z = (m_on - m_off) / std::sqrt(v_on + v_off);
    std::printf("roulette %s: mean %.6f (+- %.6f) vs %.6f (+- %.6f) without, z = %.2f\n",
                sampler == Sampler::sobol ? "sobol" : "random", m_on, std::sqrt(v_on), m_off,
                std::sqrt(v_off), z);
    EXPECT_LT(std::abs(z), 4.0);
    EXPECT_NEAR(m_on, m_off, 0.002 * m_off);  // and close in absolute terms
  }
}

// In the closed furnace every pixel has the same expectation, Le (1 - rho^(B+1)) / (1 - rho), and the
// pixels are independent estimates: with roulette their mean over the image must match it within 4
// standard errors; with rho = 1 the roulette never stops a path and every pixel stays exact.
TEST(RussianRoulette, FurnaceMeanIsExact) {
  std::ifstream in(STATEPACK_FURNACE_SCENE);
  std::stringstream text;
  text << in.rdbuf();
  for (double rho : {0.5, 1.0}) {
    std::string json =
        std::regex_replace(text.str(), std::regex(R"("albedo": \[0\.5, 0\.5, 0\.5\])"),
                           rho == 1.0 ? R"("albedo": [1, 1, 1])" : R"("albedo": [0.5, 0.5, 0.5])");
    const std::string path = std::string(STATEPACK_TEST_OUTPUT_DIR) + "/furnace_roulette.json";
    std::filesystem::create_directories(STATEPACK_TEST_OUTPUT_DIR);
    std::ofstream(path) << json;
    auto scene = load_scene(path);
    ASSERT_TRUE(scene) << scene.error().message;
    RenderSettings s;
    s.bounces = 8;
    s.roulette_start = 1;
    const double expected = rho == 1.0 ? 9.0 : (1.0 - std::pow(rho, 9)) / (1.0 - rho);
    auto images = render_seeds(*scene, s, 40, 30, 64, 1);
    ASSERT_EQ(images.size(), 1u);
    std::vector<double> pixels;
    for (size_t i = 0; i < images[0].size(); i += 4) pixels.push_back(images[0][i]);
    auto [mean, variance] = mean_and_variance_of_mean(pixels);
    std::printf("furnace rho %.1f with roulette: %.6f +- %.6f (exact %.6f)\n", rho, mean, std::sqrt(variance),
                expected);
    if (rho == 1.0) {
      for (double p : pixels) ASSERT_NEAR(p, expected, 1e-5 * expected);
    } else {
      EXPECT_GT(variance, 0.0) << "roulette played no part";
      EXPECT_LT(std::abs(mean - expected), 4 * std::sqrt(variance));
    }
  }
}

// Pure BSDF sampling and MIS (with either light sampling) with the Sobol sampler estimate the same
// integral too.
TEST(EstimatorVariants, SobolBsdfAndMisMatchTheCpuReferencePerPixel) {
  auto scene = load_scene(STATEPACK_DEFAULT_SCENE);
  ASSERT_TRUE(scene);
  RenderSettings reference_settings;
  reference_settings.bounces = 3;
  reference_settings.seed = 1000;
  reference_settings.next_event_estimation = false;
  const ReferenceImage bsdf_reference = render_reference(*scene, reference_settings, 32, 24, 2048);
  RenderSettings s;
  s.bounces = 3;
  s.estimator = Estimator::bsdf;
  s.next_event_estimation = false;
  EXPECT_GE(pass_rate("bsdf sobol", render_seeds(*scene, s, 32, 24, 128, 16), bsdf_reference), 0.9975);
  s.estimator = Estimator::mis;
  s.next_event_estimation = true;
  for (LightSampling light : {LightSampling::solid_angle, LightSampling::area}) {
    s.light_sampling = light;
    const std::string name = light == LightSampling::area ? "mis sobol area" : "mis sobol solid-angle";
    EXPECT_GE(pass_rate(name, render_seeds(*scene, s, 32, 24, 64, 16), bsdf_reference), 0.9975) << name;
  }
}

}  // namespace
