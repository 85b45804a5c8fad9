#version 450
layout(location = 0) in vec3 barycentric;
layout(location = 0) out vec4 color;

// The evaluation shader's coordinate: only a pipeline that tessellated can draw it.
void main() { color = vec4(barycentric, 1.0); }
