#version 450
// Resolve: the accumulated mean radiance, scaled by the exposure, to the target (an sRGB target
// encodes it; the headless float outputs read the accumulation image directly).
// Vulkan takes the exposure as a push constant; OpenGL (--opengl) has none: a uniform block there.
layout(set = 0, binding = 0, rgba32f) uniform readonly image2D accumulation;
#ifdef VULKAN
layout(push_constant) uniform Params { float exposure; } params;
#else
layout(std140, binding = 1) uniform Params { float exposure; } params;
#endif
layout(location = 0) out vec4 out_color;

void main() {
  vec3 radiance = imageLoad(accumulation, ivec2(gl_FragCoord.xy)).rgb;
  out_color = vec4(radiance * params.exposure, 1.0);
}
