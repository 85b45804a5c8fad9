#version 450
// The work group's width is a specialization constant (SpecId 0): what a pipeline or the modify
// callback sets it to decides the size Vulkan sees.
layout(local_size_x_id = 0) in;
layout(constant_id = 0) const uint kGroupX = 1u;
layout(set = 0, binding = 0) buffer Result { uint value[]; } result;
void main() { result.value[gl_LocalInvocationID.x] = kGroupX; }
