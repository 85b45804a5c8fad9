#version 450
// Vulkan-only constructs on purpose: push constants, descriptor sets, a separate texture and sampler.
layout(push_constant) uniform Tint {
  vec4 scale;
  vec4 bias;
} tint;
layout(set = 1, binding = 0) uniform texture2D source;
layout(set = 0, binding = 1) uniform sampler point_sampler;

layout(location = 0) in vec2 uv;
layout(location = 0) out vec4 color;

void main() { color = texture(sampler2D(source, point_sampler), uv) * tint.scale + tint.bias; }
