#version 450
// Resolve: the accumulated mean radiance, scaled by the exposure, to the target (an sRGB target
// encodes it; the headless float outputs read the accumulation image directly). The image may have
// been traced at 1/divisor of the target's size (the window while the view moves): each target pixel
// then shows the traced pixel it falls in.
// Vulkan takes the parameters as push constants; OpenGL (--opengl) has none: a uniform block there.
layout(set = 0, binding = 0, rgba32f) uniform readonly image2D accumulation;
#ifdef VULKAN
layout(push_constant) uniform Params { float exposure; uint divisor; } params;
#else
layout(std140, binding = 1) uniform Params { float exposure; uint divisor; } params;
#endif
layout(location = 0) out vec4 out_color;

void main() {
  vec3 radiance = imageLoad(accumulation, ivec2(gl_FragCoord.xy) / int(max(params.divisor, 1u))).rgb;
  out_color = vec4(radiance * params.exposure, 1.0);
}
