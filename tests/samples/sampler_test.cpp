// The path tracer's low-discrepancy sampler (samples/path_tracer/sampler.hpp, bit for bit the shader's,
// see rng_test.cpp): every 2-D pair of every pixel is stratified over every prefix of samples, pixels
// are decorrelated, and independent random numbers fail the same checks.
#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <vector>

#include "path_tracer/sampler.hpp"

namespace {

using statepack::path_tracer::sample_words;
using statepack::path_tracer::Sampler;
using Point = std::array<uint32_t, 2>;

// The cell of a 32-bit fraction in a grid of 2^bits.
uint32_t cell(uint32_t word, uint32_t bits) {
  return bits == 0 ? 0 : word >> (32 - bits);
}

// Points 0..n-1 of one 2-D pair (0: light u, v; 1: bounce u, v) of pixel (x, y) at `bounce`.
std::vector<Point> pair_points(Sampler sampler, uint32_t x, uint32_t y, uint32_t seed, uint32_t bounce,
                               int pair, uint32_t n) {
  std::vector<Point> points;
  for (uint32_t i = 0; i < n; ++i) {
    auto w = sample_words(sampler, x, y, i, seed, bounce);
    points.push_back({w[2 * pair], w[2 * pair + 1]});
  }
  return points;
}

// Whether every prefix of `points` is as even as a (0,2)-sequence allows: for every elementary interval
// of area 2^-k (2^a by 2^(k-a) cells), the first N points put between floor(N / 2^k) and
// floor(N / 2^k) + popcount(N mod 2^k) points in each cell. (A prefix is a union of aligned blocks of
// 2^m samples, one per binary digit of N; each block of 2^m >= 2^k points fills every cell equally, each
// smaller one puts at most one point in a cell.) At N = 2^k this is exact stratification.
bool prefixes_stratified(const std::vector<Point>& points, uint32_t max_k) {
  for (uint32_t k = 0; k <= max_k; ++k) {
    for (uint32_t a = 0; a <= k; ++a) {
      std::vector<uint32_t> count(size_t(1) << k, 0);
      for (uint32_t n = 1; n <= points.size(); ++n) {
        ++count[(cell(points[n - 1][0], a) << (k - a)) | cell(points[n - 1][1], k - a)];
        const uint32_t low = n >> k, high = low + uint32_t(std::popcount(n & ((1u << k) - 1)));
        for (uint32_t c : count)
          if (c < low || c > high) return false;
      }
    }
  }
  return true;
}

TEST(Sampler, EveryPairOfEveryPixelIsStratifiedOverEveryPrefix) {
  for (auto [x, y] : {std::pair{0u, 0u}, std::pair{17u, 3u}, std::pair{639u, 479u}})
    for (uint32_t seed : {1u, 7919u})
      for (uint32_t bounce : {0u, 1u, 7u})
        for (int pair : {0, 1})
          EXPECT_TRUE(prefixes_stratified(pair_points(Sampler::sobol, x, y, seed, bounce, pair, 256), 8))
              << "pixel " << x << "," << y << " seed " << seed << " bounce " << bounce << " pair " << pair;
}

// Large sample counts: the first 2^12 points are a (0,12,2)-net, and so is the next block of 2^12.
TEST(Sampler, PowerOfTwoBlocksAreNets) {
  const uint32_t k = 12, n = 1u << k;
  auto points = pair_points(Sampler::sobol, 5, 9, 3, 2, 1, 2 * n);
  for (uint32_t block = 0; block < 2; ++block)
    for (uint32_t a = 0; a <= k; ++a) {
      std::vector<uint8_t> seen(n, 0);
      for (uint32_t i = block * n; i < (block + 1) * n; ++i)
        seen[(cell(points[i][0], a) << (k - a)) | cell(points[i][1], k - a)] = 1;
      EXPECT_EQ(std::count(seen.begin(), seen.end(), 1), n) << "block " << block << ", 2^" << a << " columns";
    }
}

// The check has teeth: independent random numbers fail it already at 16 points, for every pair.
TEST(Sampler, IndependentRandomNumbersAreNotStratified) {
  int stratified = 0;
  for (uint32_t x = 0; x < 8; ++x)
    for (int pair : {0, 1})
      stratified += prefixes_stratified(pair_points(Sampler::random, x, 0, 1, 0, pair, 16), 4);
  EXPECT_EQ(stratified, 0);
}

// Per-pixel scrambling: the same sample of neighbouring pixels is uncorrelated, and the light and
// bounce pairs of one pixel are uncorrelated with each other (Pearson r within 5 standard errors).
TEST(Sampler, PixelsAndPairsAreDecorrelated) {
  auto unit = [](uint32_t w) { return double(w >> 8) / 16777216.0; };
  auto correlation = [](const std::vector<std::pair<double, double>>& v) {
    double sx = 0, sy = 0, sxx = 0, syy = 0, sxy = 0, n = double(v.size());
    for (auto [a, b] : v) sx += a, sy += b, sxx += a * a, syy += b * b, sxy += a * b;
    return (sxy - sx * sy / n) / std::sqrt((sxx - sx * sx / n) * (syy - sy * sy / n));
  };
  std::vector<std::pair<double, double>> neighbours, pairs;
  for (uint32_t y = 0; y < 128; ++y)
    for (uint32_t x = 0; x < 128; ++x) {
      auto here = sample_words(Sampler::sobol, x, y, 5, 11, 1);
      auto right = sample_words(Sampler::sobol, x + 1, y, 5, 11, 1);
      neighbours.push_back({unit(here[0]), unit(right[0])});
    }
  for (uint32_t i = 0; i < 16384; ++i) {
    auto w = sample_words(Sampler::sobol, 3, 4, i, 11, 2);
    pairs.push_back({unit(w[0]), unit(w[2])});
  }
  const double limit = 5.0 / std::sqrt(16384.0);
  EXPECT_LT(std::abs(correlation(neighbours)), limit);
  EXPECT_LT(std::abs(correlation(pairs)), limit);
  // Different seeds give different scramblings.
  EXPECT_NE(sample_words(Sampler::sobol, 3, 4, 0, 1, 0), sample_words(Sampler::sobol, 3, 4, 0, 2, 0));
}

}  // namespace
