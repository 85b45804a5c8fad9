// Random numbers for the path tracer: counter-based, so any sample can be reproduced alone and the
// CPU (samples/path_tracer/random.hpp) computes the same bits (tests/samples/rng_test.cpp checks it).

#ifndef PATH_TRACER_RANDOM_GLSL
#define PATH_TRACER_RANDOM_GLSL

// pcg4d (Jarzynski and Olano 2020): four independent 32-bit words per call.
uvec4 pcg4d(uvec4 v) {
  v = v * 1664525u + 1013904223u;
  v.x += v.y * v.w; v.y += v.z * v.x; v.z += v.x * v.y; v.w += v.y * v.z;
  v ^= v >> 16u;
  v.x += v.y * v.w; v.y += v.z * v.x; v.z += v.x * v.y; v.w += v.y * v.z;
  return v;
}
// [0, 1): the top 24 bits, exactly representable.
vec4 to_unit(uvec4 w) { return vec4(w >> 8u) * (1.0 / 16777216.0); }

#endif
