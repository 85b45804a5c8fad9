#version 450
// Samples a 2x2 texture at uv * 2: with a point-filtering, repeating sampler the texture appears twice
// across the target. Only the archive's immutable sampler says "point" and "repeat".
layout(set = 0, binding = 0) uniform sampler2D checker;
layout(location = 0) in vec2 in_uv;
layout(location = 0) out vec4 out_color;
void main() { out_color = texture(checker, in_uv * 2.0); }
