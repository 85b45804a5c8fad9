#version 450
// Each stage declares its own view of the push constants and of a uniform block: the members it uses,
// at their offsets (valid Vulkan). OpenGL links one definition per block; statepack merges the views.
layout(push_constant) uniform Push
{
    vec4 offset;  // bytes 0-15
} push;

layout(set = 0, binding = 0) uniform Params
{
    vec4 scale;  // bytes 0-15
} params;

void main()
{
    vec2 uv = vec2((gl_VertexIndex << 1) & 2, gl_VertexIndex & 2);
    gl_Position = vec4((uv * 2.0 - 1.0) * params.scale.xy + push.offset.xy, 0.0, 1.0);
}
