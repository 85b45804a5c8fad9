#version 450
// Generated code renumbers its lines; GLSL's #line may also give a source-string number (3 here),
// which glslang then prints where the file name goes.
#line 20 3
layout(location = 0) out vec4 color;
void main() { color = vec4(1.0) + undefined_after_line; }
