// The four numbers a path uses at one bounce (light sample u, v; bounce direction u, v), from either
// sampler; the CPU twin is samples/path_tracer/sampler.hpp (same bits, tested).
#ifndef PATH_TRACER_SAMPLER_GLSL
#define PATH_TRACER_SAMPLER_GLSL
#include "random.glsl"
#include "sobol.glsl"

// Independent random numbers: pcg4d of (pixel, sample, seed + bounce * golden ratio).
uvec4 random_words(uvec2 pixel, uint sample_index, uint seed, uint bounce) {
  return pcg4d(uvec4(pixel, sample_index, seed + bounce * 0x9E3779B9u));
}

// Low discrepancy: each 2-D pair (2 * bounce: light, 2 * bounce + 1: bounce direction) is its own
// scrambled Sobol sequence over the sample index, with seeds hashed from (pixel, seed, pair). Pixels
// and pairs are therefore decorrelated (white noise between pixels, independent pads between pairs),
// while each pair of one pixel is stratified over any prefix of samples.
uvec2 sobol_pair(uvec2 pixel, uint sample_index, uint seed, uint pair) {
  uvec4 seeds = pcg4d(uvec4(pixel, seed, 0x80000000u | pair));
  return scrambled_sobol(sample_index, seeds.xyz);
}

uvec4 sample_words(bool sobol, uvec2 pixel, uint sample_index, uint seed, uint bounce) {
  if (!sobol) return random_words(pixel, sample_index, seed, bounce);
  return uvec4(sobol_pair(pixel, sample_index, seed, 2u * bounce),
               sobol_pair(pixel, sample_index, seed, 2u * bounce + 1u));
}

// The Russian-roulette decision at a bounce. With Sobol it is one more scrambled sequence (pair 16 +
// bounce, beyond the 2 * 8 pairs of the path), so that over any prefix of samples the fraction of
// paths that go on is close to q instead of binomially spread around it; otherwise independent.
float roulette_unit(bool sobol, uvec2 pixel, uint sample_index, uint seed, uint bounce) {
  if (sobol) return to_unit(uvec4(sobol_pair(pixel, sample_index, seed, 16u + bounce), 0u, 0u)).x;
  return to_unit(pcg4d(uvec4(pixel, sample_index, ~(seed + bounce * 0x9E3779B9u)))).x;
}

// The choice of one light without area at a bounce (--delta-lights one): the second coordinate of the
// roulette's pair, so it is stratified the same way and independent of the decision.
float light_choice_unit(bool sobol, uvec2 pixel, uint sample_index, uint seed, uint bounce) {
  if (sobol) return to_unit(uvec4(sobol_pair(pixel, sample_index, seed, 16u + bounce), 0u, 0u)).y;
  return to_unit(pcg4d(uvec4(pixel, sample_index, ~(seed + bounce * 0x9E3779B9u)))).y;
}

#endif
