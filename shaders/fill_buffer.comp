#version 450
// Writes values[i] = i * multiplier + offset for i < count.
layout(local_size_x = 64) in;

layout(set = 0, binding = 0) buffer Values { uint values[]; };
layout(push_constant) uniform Params {
  uint count;
  uint multiplier;
  uint offset;
} params;

void main() {
  uint i = gl_GlobalInvocationID.x;
  if (i < params.count) values[i] = i * params.multiplier + params.offset;
}
