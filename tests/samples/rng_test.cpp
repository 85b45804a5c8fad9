// The path tracer's random numbers: the GPU (lavapipe, via a pipeline from an archive) produces
// exactly the CPU's bits, and the numbers pass a 2-D chi-square test and a neighbour-correlation test.
#include <cmath>
#include <cstring>

#include "common/vulkan_test_fixture.hpp"
#include "path_tracer/sampler.hpp"

namespace statepack::testing {
namespace {

class Random : public VulkanTest {
 protected:
  // pcg4d for every pixel of a width x height grid at one sample and dimension, computed on the GPU;
  // with `sobol`, the Sobol sampler's words at `bounce` with seed `dimension`.
  std::vector<std::array<uint32_t, 4>> gpu_words(uint32_t width, uint32_t height, uint32_t sample,
                                                 uint32_t dimension, bool sobol = false,
                                                 uint32_t bounce = 0) {
    auto dearchiver = Dearchiver::create({vk_->physical_device, vk_->device});
    auto archive = Archive::from_file(STATEPACK_RNG_ARCHIVE);
    EXPECT_TRUE(archive) << archive.error().message;
    EXPECT_TRUE(dearchiver->add_archive(std::move(*archive)));
    auto pso = dearchiver->unpack_compute("RNG Dump PSO");
    EXPECT_TRUE(pso) << pso.error().message;
    const BindingInfo* words = (*pso)->find_binding("Words");
    const VkDeviceSize size = VkDeviceSize(width) * height * 16;
    auto buffer = bootstrap::create_host_buffer(*vk_, size, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT);
    auto set = bootstrap::bind_storage_buffer(*vk_, (*pso)->set_layouts.at(words->set), words->binding,
                                              (*buffer)->buffer);
    const uint32_t params[6] = {width, height, sample, dimension, sobol ? 1u : 0u, bounce};
    auto done = vk_->submit_and_wait([&](VkCommandBuffer cmd) {
      vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, (*pso)->pipeline);
      vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, (*pso)->layout, words->set, 1,
                              &(*set)->set, 0, nullptr);
      vkCmdPushConstants(cmd, (*pso)->layout, (*pso)->push_constant_stages, 0, sizeof params, params);
      vkCmdDispatch(cmd, (width + 7) / 8, (height + 7) / 8, 1);
    });
    EXPECT_TRUE(done);
    std::vector<std::array<uint32_t, 4>> out(size_t(width) * height);
    std::memcpy(out.data(), (*buffer)->mapped, size);
    return out;
  }
};

TEST_F(Random, GpuAndCpuProduceTheSameBits) {
  for (uint32_t sample : {0u, 1u, 977u}) {
    for (uint32_t dimension : {1u, 1u + 0x9E3779B9u * 5u}) {
      auto words = gpu_words(64, 48, sample, dimension);
      for (uint32_t y = 0; y < 48; ++y)
        for (uint32_t x = 0; x < 64; ++x)
          ASSERT_EQ(words[y * 64 + x], path_tracer::pcg4d({x, y, sample, dimension}))
              << "pixel " << x << "," << y << " sample " << sample;
    }
  }
}

// The scrambled Sobol sampler: the same bits on both sides for early, late and large sample indices,
// first and last bounces, and two seeds.
TEST_F(Random, SobolGpuAndCpuProduceTheSameBits) {
  for (uint32_t sample : {0u, 1u, 977u, 65535u, 1u << 20}) {
    for (uint32_t bounce : {0u, 7u}) {
      for (uint32_t seed : {1u, 7919u * 3u}) {
        auto words = gpu_words(32, 24, sample, seed, true, bounce);
        for (uint32_t y = 0; y < 24; ++y)
          for (uint32_t x = 0; x < 32; ++x)
            ASSERT_EQ(words[y * 32 + x],
                      path_tracer::sample_words(path_tracer::Sampler::sobol, x, y, sample, seed, bounce))
                << "pixel " << x << "," << y << " sample " << sample << " bounce " << bounce;
      }
    }
  }
}

TEST_F(Random, UniformInTwoDimensionsAndUncorrelatedBetweenNeighbours) {
  constexpr uint32_t kWidth = 512, kHeight = 512, kBins = 64;
  auto words = gpu_words(kWidth, kHeight, 3, 7);
  // Chi-square over 64 x 64 cells of (u0, u1): 4095 degrees of freedom, standard deviation ~90.5.
  std::vector<uint32_t> cells(kBins * kBins, 0);
  for (const auto& w : words)
    ++cells[uint32_t(path_tracer::to_unit(w[0]) * kBins) * kBins +
            uint32_t(path_tracer::to_unit(w[1]) * kBins)];
  const double expected = double(words.size()) / (kBins * kBins);
  double chi2 = 0;
  for (uint32_t c : cells) chi2 += (c - expected) * (c - expected) / expected;
  EXPECT_NEAR(chi2, 4095.0, 5 * 90.5) << "chi-square of the (u0, u1) grid";
  // The same word of horizontally neighbouring pixels: Pearson correlation near 0.
  double sx = 0, sy = 0, sxx = 0, syy = 0, sxy = 0;
  size_t n = 0;
  for (uint32_t y = 0; y < kHeight; ++y)
    for (uint32_t x = 0; x + 1 < kWidth; ++x, ++n) {
      double a = path_tracer::to_unit(words[y * kWidth + x][2]),
             b = path_tracer::to_unit(words[y * kWidth + x + 1][2]);
      sx += a, sy += b, sxx += a * a, syy += b * b, sxy += a * b;
    }
  const double dn = double(n);
  const double r = (sxy - sx * sy / dn) / std::sqrt((sxx - sx * sx / dn) * (syy - sy * sy / dn));
  EXPECT_LT(std::abs(r), 5.0 / std::sqrt(dn)) << "neighbour correlation " << r;
  // And the four words of one call are not copies of each other.
  size_t equal = 0;
  for (const auto& w : words) equal += (w[0] == w[1]) + (w[2] == w[3]);
  EXPECT_LT(equal, 4u);
}

}  // namespace
}  // namespace statepack::testing
