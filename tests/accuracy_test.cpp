// Exact anchors for the path tracer, on lavapipe with validation on (the program fails on any
// message): the closed-room furnace, direct light under the rectangular light against the analytic
// value, and next-event estimation agreeing with pure BSDF sampling.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <numeric>
#include <regex>
#include <sstream>

#include "reference.hpp"
#include "run_command.hpp"

namespace {

namespace fs = std::filesystem;

std::vector<float> render(const std::string& name, const std::string& args) {
  fs::path out = fs::path(STATEPACK_TEST_OUTPUT_DIR) / (name + ".pfm");
  fs::create_directories(out.parent_path());
  auto result = statepack::testing::run_command(std::string("'") + STATEPACK_PATH_TRACER +
                                                "' --headless --out '" + out.string() + "' " + args);
  EXPECT_EQ(result.exit_code, 0) << result.output;
  std::ifstream file(out, std::ios::binary);
  std::string magic;
  uint32_t w = 0, h = 0;
  float scale = 0;
  file >> magic >> w >> h >> scale;
  file.get();
  std::vector<float> rgb(size_t(w) * h * 3);
  file.read(reinterpret_cast<char*>(rgb.data()), std::streamsize(rgb.size() * sizeof(float)));
  EXPECT_TRUE(file) << out;
  return rgb;  // rows bottom to top; the tests below do not care
}

// The furnace scene with every albedo set to `rho`.
fs::path furnace_scene(double rho) {
  std::ifstream in(STATEPACK_FURNACE_SCENE);
  std::stringstream text;
  text << in.rdbuf();
  std::ostringstream value;
  value << rho;
  std::string scene =
      std::regex_replace(text.str(), std::regex(R"("albedo": \[0\.5, 0\.5, 0\.5\])"),
                         "\"albedo\": [" + value.str() + ", " + value.str() + ", " + value.str() + "]");
  fs::path path = fs::path(STATEPACK_TEST_OUTPUT_DIR) / ("furnace_" + value.str() + ".json");
  fs::create_directories(path.parent_path());
  std::ofstream(path) << scene;
  return path;
}

// Closed room, every surface emitting Le = 1 with albedo rho: every path, however it bounces, carries
// exactly Le * (1 + rho + ... + rho^B); any leak through a wall or corner, or a lost bounce, shows.
TEST(Accuracy, FurnaceIsExactForEveryPixelAndEstimator) {
  for (double rho : {0.5, 1.0}) {
    fs::path scene = furnace_scene(rho);
    for (int bounces : {1, 3, 8}) {
      const double expected = rho == 1.0 ? bounces + 1.0 : (1.0 - std::pow(rho, bounces + 1)) / (1.0 - rho);
      for (const char* estimator : {"", "--no-nee"}) {
        SCOPED_TRACE("rho " + std::to_string(rho) + ", B " + std::to_string(bounces) + " " + estimator);
        auto image =
            render("furnace", "--scene '" + scene.string() + "' --width 40 --height 30 --spp 8 --bounces " +
                                  std::to_string(bounces) + " " + estimator);
        size_t wrong = 0;
        for (float v : image) wrong += std::abs(v - expected) > 1e-5 * expected;
        EXPECT_EQ(wrong, 0u) << "of " << image.size() << " values differ from " << expected;
      }
    }
  }
}

// Direct light at the floor point (3.5, -4.925, 3.5) of the default scene, seen straight down by the
// centre pixel: rho/pi * E, with E from the closed-form rectangle-to-point formula (reference
// pathtracer-anchor.md §4.2): 0.140539 for albedo 0.5 and the 3x3 light of radiance 15 at y = 4.88.
TEST(Accuracy, DirectLightMatchesTheAnalyticRectangle) {
  fs::path scene = fs::path(STATEPACK_TEST_OUTPUT_DIR) / "look_down.json";
  {
    std::ifstream in(STATEPACK_DEFAULT_SCENE);
    std::stringstream text;
    text << in.rdbuf();
    std::string s = std::regex_replace(text.str(), std::regex(R"("camera": \{[^}]*\})"),
                                       R"("camera": { "position": [3.5, 0, 3.5], "pitch_degrees": -90 })");
    std::ofstream(scene) << s;
  }
  // Four independent seeds give the mean and its spread.
  std::vector<double> centre;
  for (int seed = 1; seed <= 4; ++seed) {
    auto image =
        render("direct", "--scene '" + scene.string() +
                             "' --width 9 --height 9 --spp 16384 --samples-per-frame 32 --bounces 1 --seed " +
                             std::to_string(seed));
    centre.push_back(image[(4 * 9 + 4) * 3]);  // the centre pixel, red channel
  }
  const double n = double(centre.size());
  const double mean = std::accumulate(centre.begin(), centre.end(), 0.0) / n;
  double var = 0;
  for (double c : centre) var += (c - mean) * (c - mean);
  const double stderr_mean = std::sqrt(var / (n - 1) / n);
  EXPECT_NEAR(mean, 0.140539, std::max(5 * stderr_mean, 1e-4)) << "standard error " << stderr_mean;
  std::printf("direct light at the floor point: %.6f +- %.6f (analytic 0.140539)\n", mean, stderr_mean);
  EXPECT_LT(stderr_mean, 0.002) << "too noisy to mean anything";
}

// Next-event estimation and pure BSDF sampling estimate the same integral: their image means must
// agree within the noise (z-test over independent seeds).
TEST(Accuracy, NextEventEstimationAgreesWithBsdfSampling) {
  auto image_mean = [](const std::vector<float>& image) {
    return std::accumulate(image.begin(), image.end(), 0.0) / double(image.size());
  };
  std::vector<double> nee, bsdf;
  for (int seed = 1; seed <= 4; ++seed) {
    const std::string common = "--width 32 --height 24 --bounces 3 --seed " + std::to_string(seed);
    nee.push_back(image_mean(render("nee", common + " --spp 256")));
    bsdf.push_back(image_mean(render("bsdf", common + " --spp 2048 --no-nee")));
  }
  auto stats = [](const std::vector<double>& v) {
    const double n = double(v.size());
    double m = std::accumulate(v.begin(), v.end(), 0.0) / n, s = 0;
    for (double x : v) s += (x - m) * (x - m);
    return std::pair{m, s / (n - 1) / n};  // mean, variance of the mean
  };
  auto [m_nee, v_nee] = stats(nee);
  auto [m_bsdf, v_bsdf] = stats(bsdf);
  const double z = (m_nee - m_bsdf) / std::sqrt(v_nee + v_bsdf);
  EXPECT_LT(std::abs(z), 4.0) << "NEE " << m_nee << " vs BSDF " << m_bsdf;
  EXPECT_NEAR(m_nee, m_bsdf, 0.02 * m_nee);  // and close in absolute terms
}

// The GPU image against the double-precision CPU reference of the same integral (independent seeds),
// pixel by pixel: a z-test per pixel and channel at a Sidak-corrected 1 % family-wise level; at least
// 99.75 % must pass (pixels on geometric edges may hit another surface in float than in double).
TEST(Accuracy, GpuMatchesTheCpuReferencePerPixel) {
  using namespace statepack::path_tracer;
  constexpr uint32_t kWidth = 48, kHeight = 36, kGpuSpp = 256, kCpuSpp = 1024;
  auto scene = load_scene(STATEPACK_DEFAULT_SCENE);
  ASSERT_TRUE(scene) << scene.error().message;
  RenderSettings settings;
  settings.bounces = 3;
  settings.seed = 1000;  // independent of the GPU's seed below
  ReferenceImage reference = render_reference(*scene, settings, kWidth, kHeight, kCpuSpp);
  auto gpu =
      render("versus_cpu", "--width 48 --height 36 --bounces 3 --seed 1 --samples-per-frame 32 --spp " +
                               std::to_string(kGpuSpp));
  const size_t tests = size_t(kWidth) * kHeight * 3;
  const double alpha = 0.01, per_test = 1.0 - std::pow(1.0 - alpha, 1.0 / double(tests));
  // Two-sided normal quantile by bisection on erfc.
  double lo = 0, hi = 10;
  for (int i = 0; i < 100; ++i) {
    double mid = (lo + hi) / 2;
    (std::erfc(mid / std::sqrt(2.0)) > per_test ? lo : hi) = mid;
  }
  const double z_critical = lo;
  size_t failed = 0;
  double worst = 0;
  for (uint32_t y = 0; y < kHeight; ++y) {
    for (uint32_t x = 0; x < kWidth; ++x) {
      for (int c = 0; c < 3; ++c) {
        const size_t r = (size_t(y) * kWidth + x) * 3 + c;
        const size_t g = (size_t(kHeight - 1 - y) * kWidth + x) * 3 + c;  // PFM rows run bottom to top
        const double var = reference.variance[r];
        const double diff = double(gpu[g]) - reference.mean[r];
        const double z = var > 0 ? std::abs(diff) / std::sqrt(var / kGpuSpp + var / kCpuSpp)
                                 : (std::abs(diff) < 1e-4 ? 0 : 1e9);
        worst = std::max(worst, std::min(z, 1e3));
        failed += z > z_critical;
      }
    }
  }
  const double pass_rate = 1.0 - double(failed) / double(tests);
  std::printf("GPU vs CPU reference: %.3f %% of %zu pixel channels pass |z| < %.2f (worst %.1f)\n",
              100 * pass_rate, tests, z_critical, worst);
  EXPECT_GE(pass_rate, 0.9975) << failed << " of " << tests << " pixel channels fail";
}

}  // namespace
