// Owen-scrambled 2-D Sobol points on the CPU, bit for bit those of shaders/path_tracer/sobol.glsl
// (Burley 2020, "Practical Hash-based Owen Scrambling"; see that file for why each step is there).
#pragma once

#include <array>
#include <cstdint>

namespace statepack::path_tracer {

inline uint32_t reverse_bits(uint32_t x) {
  x = (x >> 16u) | (x << 16u);
  x = ((x & 0xff00ff00u) >> 8u) | ((x & 0x00ff00ffu) << 8u);
  x = ((x & 0xf0f0f0f0u) >> 4u) | ((x & 0x0f0f0f0fu) << 4u);
  x = ((x & 0xccccccccu) >> 2u) | ((x & 0x33333333u) << 2u);
  return ((x & 0xaaaaaaaau) >> 1u) | ((x & 0x55555555u) << 1u);
}

// Output bit b is input bit b flipped by a function of the lower bits and the seed: an Owen scramble
// of bit-reversed fixed-point numbers.
inline uint32_t owen_hash(uint32_t x, uint32_t seed) {
  x ^= x * 0x3d20adeau;
  x += seed;
  x *= (seed >> 16u) | 1u;
  x ^= x * 0x05526c56u;
  x ^= x * 0x53a22864u;
  return x;
}

// Sobol dimensions 0 and 1 of `index`, bit-reversed.
inline std::array<uint32_t, 2> sobol_reversed(uint32_t index) {
  uint32_t y = 0, r = 1;
  for (uint32_t i = index; i != 0; i >>= 1u, r ^= r << 1u)
    if (i & 1u) y ^= r;
  return {index, y};
}

// Point `index` with seeds {shuffle, scramble x, scramble y}, as 32-bit fractions.
inline std::array<uint32_t, 2> scrambled_sobol(uint32_t index, std::array<uint32_t, 3> seeds) {
  const uint32_t shuffled = reverse_bits(owen_hash(reverse_bits(index), seeds[0]));
  const auto p = sobol_reversed(shuffled);
  return {reverse_bits(owen_hash(p[0], seeds[1])), reverse_bits(owen_hash(p[1], seeds[2]))};
}

}  // namespace statepack::path_tracer
