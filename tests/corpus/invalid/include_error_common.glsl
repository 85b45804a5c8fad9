// Shared by include_error_a.frag and include_error_b.frag.
float scaled(float x) {
  return x * undefined_scale;
}
