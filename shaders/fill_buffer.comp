#version 450
// Writes values[i] = i * multiplier + offset for i < count.
// One source for both backends: Vulkan takes the parameters as push constants; OpenGL (GL_SPIRV, packed
// with --opengl) has none and takes them from a uniform block of the same name.
layout(local_size_x = 64) in;

layout(set = 0, binding = 0) buffer Values { uint values[]; };
#ifdef VULKAN
layout(push_constant) uniform Params {
#else
layout(std140, binding = 1) uniform Params {
#endif
  uint count;
  uint multiplier;
  uint offset;
} params;

void main() {
  uint i = gl_GlobalInvocationID.x;
  if (i < params.count) values[i] = i * params.multiplier + params.offset;
}
