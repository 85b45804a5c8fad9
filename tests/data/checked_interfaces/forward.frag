#version 450
layout(location = 0) in vec4 color;
layout(location = 1) flat in uint id;
layout(location = 0) out vec4 target;
// Half the id scales red, alpha 0.5: the blend against the cleared target halves it again.
void main() { target = vec4(color.r * float(id) * 0.5, color.g, color.b, 0.5); }
