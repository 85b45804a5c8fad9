#version 450
// per_stage_blocks.vert's partner: later members of the same blocks.
layout(push_constant) uniform Push
{
    layout(offset = 16) vec4 color;  // bytes 16-31
} push;

layout(set = 0, binding = 0) uniform Params
{
    vec4 scale;  // bytes 0-15, unused here
    vec4 tint;   // bytes 16-31
} params;

layout(location = 0) out vec4 out_color;

void main()
{
    out_color = push.color * params.tint;
}
