#version 450
layout(local_size_x = 1) in;
layout(set = 0, binding = 0) buffer Out { float v[]; } result;
void main() {
  result.v[0] = undefined_variable;
}
