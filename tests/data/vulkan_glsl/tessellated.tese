#version 450
// Each generated vertex carries its barycentric coordinate, so the colour shows the tessellation.
layout(triangles, equal_spacing, cw) in;
layout(location = 0) out vec3 barycentric;

void main() {
  barycentric = gl_TessCoord;
  gl_Position = gl_in[0].gl_Position * gl_TessCoord.x + gl_in[1].gl_Position * gl_TessCoord.y +
                gl_in[2].gl_Position * gl_TessCoord.z;
}
