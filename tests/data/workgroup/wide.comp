#version 450
// 32 x 32 x 2 = 2048 invocations: within every dimension's limit, beyond the invocation limit of most
// devices (lavapipe's is 1024) and beyond the 128 Vulkan guarantees.
layout(local_size_x = 32, local_size_y = 32, local_size_z = 2) in;
layout(set = 0, binding = 0) buffer Result { uint value[]; } result;
void main() { result.value[gl_LocalInvocationIndex] = gl_LocalInvocationIndex; }
