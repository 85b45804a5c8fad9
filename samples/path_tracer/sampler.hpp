// The numbers a path uses at one bounce, on the CPU: bit for bit shaders/path_tracer/sampler.glsl.
#pragma once

#include <array>
#include <cstdint>

#include "random.hpp"
#include "sobol.hpp"

namespace statepack::path_tracer {

// Independent random numbers (pcg4d) or per-pair scrambled Sobol sequences over the sample index.
enum class Sampler { sobol, random };

inline std::array<uint32_t, 4> random_words(uint32_t x, uint32_t y, uint32_t sample_index, uint32_t seed,
                                            uint32_t bounce) {
  return pcg4d({x, y, sample_index, seed + bounce * 0x9E3779B9u});
}

// Pair 2 * bounce drives the light sample, 2 * bounce + 1 the bounce direction.
inline std::array<uint32_t, 2> sobol_pair(uint32_t x, uint32_t y, uint32_t sample_index, uint32_t seed,
                                          uint32_t pair) {
  const auto seeds = pcg4d({x, y, seed, 0x80000000u | pair});
  return scrambled_sobol(sample_index, {seeds[0], seeds[1], seeds[2]});
}

// {light u, light v, bounce u, bounce v} of one sample at one bounce.
inline std::array<uint32_t, 4> sample_words(Sampler sampler, uint32_t x, uint32_t y, uint32_t sample_index,
                                            uint32_t seed, uint32_t bounce) {
  if (sampler == Sampler::random) return random_words(x, y, sample_index, seed, bounce);
  const auto light = sobol_pair(x, y, sample_index, seed, 2 * bounce);
  const auto dir = sobol_pair(x, y, sample_index, seed, 2 * bounce + 1);
  return {light[0], light[1], dir[0], dir[1]};
}

}  // namespace statepack::path_tracer
