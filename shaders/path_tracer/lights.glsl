// Lights without area (directional, point, spot) for next-event estimation: a bounce never hits one, so
// each is sampled at every path vertex, exactly (a delta light has one direction). Their falloff is the
// renderer's notes' (docs/path_tracer.md, "Lights"):
//   c(r) = c0 * (r0 / max(r, r_min))^2 * max(1 - (r / r_max)^4, 0)^2 [with a range] * smoothstep(t) [spot],
//   t = clamp((cos(theta_s) - cos(theta_u)) / (cos(theta_p) - cos(theta_u)), 0, 1),
// and a Lambertian surface of albedo rho reflects rho * c(r) * cos(theta_x), the convention that a white
// surface facing the light shows its colour.
// The pipeline is specialised for the kinds a scene has (kLightKinds, set at unpack from the scene), so
// a scene without them pays for none of this.

layout(constant_id = 1) const uint kLightKinds = 0u;  // 1 directional, 2 point, 4 spot
const uint LIGHT_DIRECTIONAL = 0u, LIGHT_POINT = 1u, LIGHT_SPOT = 2u;

// The light's share at x (normal n) before the surface's rho / pi and before its shadow ray:
// pi * c(r) * cos(theta_x), 0 when it is behind the surface or outside its cone or range; `l` and
// `distance` give the shadow ray. Records are laid out by gpu_lights() in samples/path_tracer/scene.cpp.
vec3 unshadowed(uint index, vec3 x, vec3 n, out vec3 l, out float distance) {
  l = vec3(0.0);
  distance = 0.0;
  Box light = scene.boxes[index];
  uint type = uint(light.center.w);
  if ((kLightKinds & (1u << type)) == 0u) return vec3(0.0);  // lets the compiler drop what is not used
  float scale = 1.0;
  if (type == LIGHT_DIRECTIONAL) {
    l = -light.emittance.xyz;
    distance = 1e30;  // shadow rays reach every box of a scene bounded by 1e6
  } else {
    vec3 to_light = light.center.xyz - x;
    distance = length(to_light);
    if (!(distance > 0.0)) return vec3(0.0);  // a light exactly at x has no direction
    l = to_light / distance;
    float q = light.half_size.w / max(distance, light.albedo.x);
    scale = q * q;
    if (light.albedo.y > 0.0) {
      float ratio = distance / light.albedo.y;
      float w = max(1.0 - ratio * ratio * ratio * ratio, 0.0);
      scale *= w * w;
    }
    if (type == LIGHT_SPOT) {
      float t = clamp((dot(light.emittance.xyz, -l) - light.albedo.z) * light.albedo.w, 0.0, 1.0);
      scale *= t * t * (3.0 - 2.0 * t);
    }
  }
  float cos_x = dot(n, l);
  if (cos_x <= 0.0 || scale <= 0.0) return vec3(0.0);
  return PI * light.half_size.rgb * (scale * cos_x);
}

vec3 shadowed(uint index, vec3 x, vec3 n, int source_box) {
  vec3 l;
  float distance;
  vec3 c = unshadowed(index, x, n, l, distance);
  if (c == vec3(0.0) || !visible(x, l, distance, source_box, -1)) return vec3(0.0);
  return c;
}

float weight(vec3 c) { return c.r + c.g + c.b; }

// Every light (exact at the vertex), or with `one` a single light chosen with probability
// w_k / sum(w), w_k its unshadowed contribution, and divided by that probability (unbiased: a light
// with w_k = 0 gives nothing either way). `u` in [0, 1) picks it. The caller checks kLightKinds != 0.
vec3 delta_lights(vec3 x, vec3 n, int source_box, bool one, float u) {
  uint first = constants.lights.x, count = constants.lights.y;
  vec3 sum = vec3(0.0), l;
  float distance;
  if (!one) {
    for (uint k = 0u; k < count; ++k) sum += shadowed(first + k, x, n, source_box);
    return sum;
  }
  float total = 0.0;
  for (uint k = 0u; k < count; ++k) total += weight(unshadowed(first + k, x, n, l, distance));
  if (!(total > 0.0)) return sum;
  // The light whose share of the running sum covers u * total; float rounding that leaves u * total at
  // or past the sum's end picks the last light with any weight, never none.
  float target = u * total, running = 0.0, chosen_distance = 0.0;
  vec3 chosen = vec3(0.0), chosen_l = vec3(0.0);
  for (uint k = 0u; k < count && !(target < running); ++k) {
    vec3 c = unshadowed(first + k, x, n, l, distance);
    float w = weight(c);
    if (w > 0.0) chosen = c, chosen_l = l, chosen_distance = distance, running += w;
  }
  if (!visible(x, chosen_l, chosen_distance, source_box, -1)) return sum;
  return chosen * (total / weight(chosen));
}
