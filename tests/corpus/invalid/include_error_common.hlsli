// Included by include_error_c.hlsl.
float scaled(float x) {
  return x * undefined_scale;
}
