// The path tracer's random numbers on the CPU, bit for bit those of shaders/path_tracer/random.glsl.
#pragma once

#include <array>
#include <cstdint>

namespace statepack::path_tracer {

// pcg4d (Jarzynski and Olano 2020): four independent 32-bit words from four 32-bit inputs.
inline std::array<uint32_t, 4> pcg4d(std::array<uint32_t, 4> v) {
  for (auto& x : v) x = x * 1664525u + 1013904223u;
  v[0] += v[1] * v[3], v[1] += v[2] * v[0], v[2] += v[0] * v[1], v[3] += v[1] * v[2];
  for (auto& x : v) x ^= x >> 16u;
  v[0] += v[1] * v[3], v[1] += v[2] * v[0], v[2] += v[0] * v[1], v[3] += v[1] * v[2];
  return v;
}

// [0, 1): the top 24 bits, exactly representable in a float.
inline float to_unit(uint32_t word) {
  return float(word >> 8u) * (1.0f / 16777216.0f);
}

}  // namespace statepack::path_tracer
