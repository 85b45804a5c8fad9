#version 450
// Path tracing with next-event estimation, one thread per pixel, starting from the G-buffer.
// Lambertian surfaces, cosine-weighted bounces, one rectangular light (the emitting face of a box).
// The accumulation image holds the running mean; each batch is merged with weight batch / total, so
// long accumulations do not drift.
#extension GL_GOOGLE_include_directive : require
#include "scene.glsl"
#include "spherical_rectangle.glsl"
#include "lights.glsl"

// The rectangular light (the emitting face of a box): false for a scene without one (set at unpack).
layout(constant_id = 0) const bool kAreaLight = true;

layout(local_size_x = 8, local_size_y = 8) in;
layout(set = 0, binding = 2, rgba32f) uniform readonly image2D g_albedo;
layout(set = 0, binding = 3, rgba32f) uniform readonly image2D g_normal;
layout(set = 0, binding = 4, rgba32f) uniform readonly image2D g_emittance;
layout(set = 0, binding = 5, r32f) uniform readonly image2D g_depth;
layout(set = 0, binding = 6, rgba32f) uniform image2D accumulation;

// Cosine-weighted direction about n; the angle is taken in [-pi, pi), where Vulkan bounds sin/cos.
vec3 cosine_direction(vec3 n, vec2 u) {
  float phi = 2.0 * PI * (u.x - 0.5);
  float r = sqrt(u.y);
  vec3 local = vec3(r * cos(phi), r * sin(phi), sqrt(max(0.0, 1.0 - u.y)));
  // Branchless orthonormal basis (Duff et al. 2017).
  float s = n.z >= 0.0 ? 1.0 : -1.0;
  float a = -1.0 / (s + n.z);
  float b = n.x * n.y * a;
  vec3 t = vec3(1.0 + s * n.x * n.x * a, s * b, -s * n.x);
  vec3 bt = vec3(b, s + n.y * n.y * a, -n.y);
  return normalize(local.x * t + local.y * bt + local.z * n);
}

// Solid-angle densities of reaching the light along a direction: by sampling the light and by cosine
// sampling at a surface with that cosine.
float light_pdf(float distance2, float cos_light, float area) { return distance2 / (cos_light * area); }
float bsdf_pdf(float cos_x) { return cos_x / PI; }
float power_heuristic(float a, float b) { return a * a / (a * a + b * b); }

// Below this solid angle the light is sampled by area instead: there cos(light) / d^2 hardly varies over
// the light, so area sampling is already close to uniform in solid angle, while the spherical
// rectangle's angle sum (four angles near pi/2 minus 2 pi) loses its digits to cancellation in float.
// The choice depends on x only, so each point uses one unbiased technique.
const float MIN_SOLID_ANGLE = 1e-3;

// Radiance from the light reaching x (normal n) along one sampled point of the emitting face, sampled
// uniformly by area or (solid_angle_sampling) uniformly in the solid angle the face subtends.
// `solid_angle` returns S when x sampled by solid angle, else 0 (MIS weights need the same density).
vec3 sample_light(vec3 x, vec3 n, int source_box, vec2 u, bool solid_angle_sampling, out float solid_angle) {
  solid_angle = 0.0;
  int light = int(constants.light.x);
  Box box = scene.boxes[light];
  int face = int(box.emittance.w);
  int axis = face / 2;
  int a1 = (axis + 1) % 3, a2 = (axis + 2) % 3;
  vec3 face_local = face_normal_local(face) * box.half_size.xyz;
  vec3 light_normal = box_normal(light, face);
  // The face emits on its outer side only: nothing reaches a point behind it or in its plane.
  if (dot(x - (box.center.xyz + to_world(light, face_local)), light_normal) <= 0.0) return vec3(0.0);
  float area = 4.0 * box.half_size[a1] * box.half_size[a2];
  vec3 y;
  if (solid_angle_sampling) {
    vec3 corner = face_local, e1 = vec3(0.0), e2 = vec3(0.0);
    corner[a1] = -box.half_size[a1];
    corner[a2] = -box.half_size[a2];
    e1[a1] = 2.0 * box.half_size[a1];
    e2[a2] = 2.0 * box.half_size[a2];
    SphericalRectangle r = spherical_rectangle(x, box.center.xyz + to_world(light, corner),
                                               to_world(light, e1), to_world(light, e2));
    if (r.solid_angle >= MIN_SOLID_ANGLE) {  // false for NaN too
      solid_angle = r.solid_angle;
      y = sample_spherical_rectangle(r, u);
    }
  }
  if (solid_angle == 0.0) {
    // A point on the emitting face, uniformly: the two axes other than the face's.
    vec3 local = face_local;
    local[a1] = (2.0 * u.x - 1.0) * box.half_size[a1];
    local[a2] = (2.0 * u.y - 1.0) * box.half_size[a2];
    y = box.center.xyz + to_world(light, local);
  }
  vec3 to_light = y - x;
  float d2 = dot(to_light, to_light);
  if (d2 < 1e-12) return vec3(0.0);  // the shading point is on the light itself
  float d = sqrt(d2);
  vec3 l = to_light / d;
  float cos_x = dot(n, l), cos_light = -dot(light_normal, l);
  if (cos_x <= 0.0 || cos_light <= 0.0) return vec3(0.0);
#if ESTIMATOR == ESTIMATOR_BASELINE
  if (!visible(x, l, d, -1, light)) return vec3(0.0);
#else
  if (!visible(x, l, d, source_box, light)) return vec3(0.0);
#endif
  // Le * cos_x / pdf in solid angle: pdf = 1 / S, or d^2 / (cos_light * A) by area. The albedo/pi of the
  // surface is applied by the caller.
  float pdf = solid_angle > 0.0 ? 1.0 / solid_angle : light_pdf(d2, cos_light, area);
  vec3 contribution = box.emittance.rgb * (solid_angle > 0.0 ? cos_x * solid_angle : cos_x * cos_light * area / d2);
#if ESTIMATOR == ESTIMATOR_MIS
  contribution *= power_heuristic(pdf, bsdf_pdf(cos_x));
#endif
  return contribution;
}

// MIS weight of a bounce from x (normal n) that reached the light's emitting face after t along dir;
// `solid_angle` is what sample_light returned at x (0: x samples the light by area).
float bsdf_hit_weight(vec3 n, vec3 dir, float t, float solid_angle) {
  int light = int(constants.light.x);
  Box box = scene.boxes[light];
  int face = int(box.emittance.w), axis = face / 2;
  float area = 4.0 * box.half_size[(axis + 1) % 3] * box.half_size[(axis + 2) % 3];
  float cos_light = -dot(box_normal(light, face), dir);
  if (cos_light <= 0.0) return 0.0;
  float pdf = solid_angle > 0.0 ? 1.0 / solid_angle : light_pdf(t * t, cos_light, area);
  return power_heuristic(bsdf_pdf(dot(n, dir)), pdf);
}

void main() {
  ivec2 pixel = ivec2(gl_GlobalInvocationID.xy);
  if (pixel.x >= int(constants.image.x) || pixel.y >= int(constants.image.y)) return;
  vec4 albedo0 = imageLoad(g_albedo, pixel);
  float depth = imageLoad(g_depth, pixel).r;
  int box0 = int(albedo0.a + 0.5) - 1;
  vec3 batch_sum = vec3(0.0);
  uint samples = constants.frame.y, bounces = constants.frame.z, flags = constants.frame.w;
  bool sobol = (flags & FLAG_SOBOL) != 0u && ESTIMATOR != ESTIMATOR_BASELINE;
  uint roulette_start = constants.light.y;
  bool solid_angle_sampling = (flags & FLAG_SOLID_ANGLE) != 0u && ESTIMATOR != ESTIMATOR_BASELINE;
  if (box0 >= 0 && depth > 0.0) {
    int face0 = int(imageLoad(g_normal, pixel).w + 0.5);
    vec3 emittance0 = imageLoad(g_emittance, pixel).rgb;
    vec3 start = surface_point(box0, face0, constants.camera_position.xyz +
                                              depth * primary_direction(vec2(pixel) + 0.5));
    for (uint s = 0u; s < samples; ++s) {
      uint sample_index = constants.frame.x + s;
      vec3 x = start, throughput = vec3(1.0), radiance = vec3(0.0);
      int box = box0, face = face0;
      bool nee = (flags & FLAG_NEE) != 0u || ESTIMATOR == ESTIMATOR_MIS;
      bool last_only = (flags & FLAG_LAST_BOUNCE_ONLY) != 0u;
      radiance += emittance0;  // light seen directly (the "zeroth" bounce)
      // NEE: B light samples; without NEE: B bounces, adding emission where a bounce lands.
      for (uint j = 0u; j < bounces; ++j) {
        if (last_only) radiance = vec3(0.0);
        vec4 u = to_unit(sample_words(sobol, uvec2(pixel), sample_index, constants.image.z, j));
#if ESTIMATOR == ESTIMATOR_BASELINE
        u.zw = u.xy;  // the tutorial drives the light sample and the bounce with one random pair
#endif
        vec3 n = box_normal(box, face);
        vec3 rho = scene.boxes[box].albedo.rgb;
        float solid_angle = 0.0;
        if (nee && kAreaLight)
          radiance += throughput * rho / PI * sample_light(x, n, box, u.xy, solid_angle_sampling, solid_angle);
        // Lights without area: every one at every vertex, whatever the estimator (no bounce finds them).
        if (kLightKinds != 0u)
          radiance += throughput * rho / PI *
                      delta_lights(x, n, box, (flags & FLAG_ONE_DELTA_LIGHT) != 0u,
                                   light_choice_unit(sobol, uvec2(pixel), sample_index, constants.image.z, j));
        // The light is sampled B times; other emitters are found by bounces, so they need the last one
        // (and MIS needs it to reach the light by the BSDF as well).
        if (nee && j + 1u == bounces && (flags & FLAG_OTHER_EMITTERS) == 0u && ESTIMATOR != ESTIMATOR_MIS) break;
        vec3 dir = cosine_direction(n, u.zw);
        throughput *= rho;  // (rho / pi) * cos / (cos / pi)
#if ESTIMATOR != ESTIMATOR_BASELINE
        // Russian roulette from bounce `roulette_start` on: the path goes on with probability q, the
        // largest throughput component (at most 1: albedos are), and is divided by q when it does, so
        // the expectation is unchanged; weak paths stop early. "Last bounce only" needs every path to
        // reach bounce B, so it plays no roulette.
        if (roulette_start != 0u && j + 1u >= roulette_start && !last_only) {
          float q = min(1.0, max(throughput.r, max(throughput.g, throughput.b)));
          if (roulette_unit(sobol, uvec2(pixel), sample_index, constants.image.z, j) >= q) break;
          throughput /= q;
        }
#endif
#if ESTIMATOR == ESTIMATOR_BASELINE
        Hit hit = trace(x, dir, -1);
#else
        Hit hit = trace(x, dir, box);
#endif
        if (hit.box < 0) break;
        vec3 bounce_normal = n;
        x = surface_point(hit.box, hit.face, x + hit.t * dir);
        box = hit.box;
        face = hit.face;
        // Emission found by a bounce counts unless next-event estimation already sampled it (the
        // light); with MIS the light's share is weighted against its light sample.
        bool light_hit = kAreaLight && box == int(constants.light.x);
#if ESTIMATOR == ESTIMATOR_MIS
        if (light_hit) radiance += throughput * emitted(box, face) * bsdf_hit_weight(bounce_normal, dir, hit.t, solid_angle);
#endif
        if (!nee || !light_hit) radiance += throughput * emitted(box, face);
      }
      batch_sum += radiance;
    }
  }
  // Running mean: mean += (batch_mean - mean) * batch / total.
  float before = float(constants.frame.x), batch = float(samples);
  vec3 mean = constants.frame.x == 0u ? vec3(0.0) : imageLoad(accumulation, pixel).rgb;
  vec3 batch_mean = batch_sum / batch;
  mean += (batch_mean - mean) * (batch / (before + batch));
  imageStore(accumulation, pixel, vec4(mean, 1.0));
}
