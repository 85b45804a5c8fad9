#version 450
#extension GL_GOOGLE_include_directive : require
#include "constants.glsl"
layout(local_size_x = 1) in;
layout(set = 0, binding = 0) buffer Out { uint value; } result;
void main() { result.value = ANSWER; }
