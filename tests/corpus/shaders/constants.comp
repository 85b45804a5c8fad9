#version 450
// Writes its specialization constants, so that a test can see which values a pipeline was created with.
layout(local_size_x = 1) in;
layout(constant_id = 0) const uint kBase = 1u;
layout(constant_id = 1) const float kScale = 1.0;
layout(constant_id = 2) const bool kNegate = false;
layout(set = 0, binding = 0) buffer Result {
  uint value;
  float scaled;
} result;
void main() {
  result.value = kNegate ? 1000u - kBase : kBase;
  result.scaled = kScale * 2.0;
}
