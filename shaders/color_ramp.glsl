// Included by gradient.frag: shows #include resolved next to the including file.
vec4 color_ramp(vec2 uv) { return vec4(uv.x, uv.y, 0.25, 1.0); }
