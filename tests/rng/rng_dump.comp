#version 450
// Writes the path tracer's random words for a grid of pixels at one sample, so tests can compare the
// GPU's bits with the CPU's: pcg4d(x, y, sample, dimension), or (mode 1) the Sobol sampler's four words
// at bounce `bounce` with seed `dimension`.
#extension GL_GOOGLE_include_directive : require
#include "path_tracer/sampler.glsl"

layout(local_size_x = 8, local_size_y = 8) in;
layout(set = 0, binding = 0, std430) writeonly buffer Words { uvec4 words[]; };
layout(push_constant) uniform Params {
  uint width;
  uint height;
  uint sample_index;
  uint dimension;
  uint mode;
  uint bounce;
} params;

void main() {
  uvec2 p = gl_GlobalInvocationID.xy;
  if (p.x >= params.width || p.y >= params.height) return;
  words[p.y * params.width + p.x] =
      params.mode == 1u ? sample_words(true, p, params.sample_index, params.dimension, params.bounce)
                        : pcg4d(uvec4(p.x, p.y, params.sample_index, params.dimension));
}
