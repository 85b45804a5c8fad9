// Scene, camera, random numbers and ray/box intersection shared by the path tracer's shaders.
// Numerics (see docs/path_tracer.md): no global epsilon; finite safe reciprocals; the box a ray leaves
// is skipped instead; hit points are snapped onto the face plane; normals are exact unit axis vectors
// (rotated back for rotated boxes) with a fixed tie order; shadow rays are bounded segments.

#include "sampler.glsl"

// ESTIMATOR (a macro set by the notation): 0 next-event estimation (or pure BSDF sampling, a run-time
// flag), 1 multiple importance sampling of both (power heuristic), 2 the tutorial's estimator as a
// baseline (shared random pair per bounce, global epsilon, no source-box exclusion or snapping).
#ifndef ESTIMATOR
#define ESTIMATOR 0
#endif
#define ESTIMATOR_MIS 1
#define ESTIMATOR_BASELINE 2

const float PI = 3.14159265358979;

struct Box {
  vec4 center;     // xyz
  vec4 half_size;  // xyz
  vec4 albedo;     // rgb
  vec4 emittance;  // rgb radiance; w: the one emitting face (0..5), 6 for every face, -1 for none
  vec4 rotation;   // x: cos, y: sin of the rotation about the box's own vertical axis
};

layout(set = 0, binding = 0, std140) uniform Constants {
  vec4 camera_position;
  vec4 camera_right;    // scaled by tan(fov/2) * aspect
  vec4 camera_up;       // scaled by tan(fov/2)
  vec4 camera_forward;
  uvec4 frame;          // x: samples before this batch, y: samples in this batch, z: bounces, w: flags
  uvec4 image;          // x: width, y: height (traced), z: seed, w: box count
  uvec4 light;          // x: index of the light's box, y: first bounce of Russian roulette (0: none),
                        // z: divisor of the traced size (1, or 2..8 while the view moves),
                        // w: the full size, width | height << 16
  uvec4 lights;         // x: index of the first light without area in `scene`, y: how many
} constants;

layout(set = 0, binding = 1, std430) readonly buffer Scene { Box boxes[]; } scene;

const uint FLAG_NEE = 1u;
const uint FLAG_LAST_BOUNCE_ONLY = 2u;
const uint FLAG_OTHER_EMITTERS = 4u;  // boxes other than the light emit: bounces must find them
const uint FLAG_SOBOL = 8u;           // scrambled Sobol points instead of independent random numbers
const uint FLAG_SOLID_ANGLE = 16u;    // sample the light uniformly in solid angle instead of by area
const uint FLAG_ONE_DELTA_LIGHT = 32u; // one light without area per vertex, chosen by its contribution

// Face index: axis * 2 + (1 if the outward normal points along -axis).
vec3 face_normal_local(int face) {
  vec3 n = vec3(0.0);
  n[face / 2] = (face % 2 == 1) ? -1.0 : 1.0;
  return n;
}

// Rotation about the vertical axis: world = center + R * local.
vec3 rotate_y(vec3 v, float c, float s) { return vec3(c * v.x - s * v.z, v.y, s * v.x + c * v.z); }
vec3 to_local(int i, vec3 v) { return rotate_y(v, scene.boxes[i].rotation.x, -scene.boxes[i].rotation.y); }
vec3 to_world(int i, vec3 v) { return rotate_y(v, scene.boxes[i].rotation.x, scene.boxes[i].rotation.y); }

vec3 box_normal(int i, int face) { return to_world(i, face_normal_local(face)); }

// Finite reciprocal: a zero component becomes +-1e20, so slabs give finite (never NaN) distances.
vec3 safe_reciprocal(vec3 d) {
  vec3 m = max(abs(d), vec3(1e-20));
  return vec3(d.x < 0.0 ? -1.0 / m.x : 1.0 / m.x, d.y < 0.0 ? -1.0 / m.y : 1.0 / m.y,
              d.z < 0.0 ? -1.0 / m.z : 1.0 / m.z);
}

// Entry distance of a ray into box i in (0, t_max), with the entry face; false when it misses.
// A ray that starts inside the box does not see it (the scene's boxes are solid; such rays only
// start on the surface of the box they leave, which is skipped).
bool intersect_box(int i, vec3 origin, vec3 dir, float t_max, out float t, out int face) {
  vec3 o = to_local(i, origin - scene.boxes[i].center.xyz);
  vec3 inv = safe_reciprocal(to_local(i, dir));
  vec3 h = scene.boxes[i].half_size.xyz;
  vec3 t1 = (-h - o) * inv, t2 = (h - o) * inv;
  vec3 near = min(t1, t2), far = max(t1, t2);
  // Entry axis with a fixed tie order (x, then y, then z): the normal is always one exact axis.
  int axis = 0;
  float t_near = near.x;
  if (near.y > t_near) { axis = 1; t_near = near.y; }
  if (near.z > t_near) { axis = 2; t_near = near.z; }
  float t_far = min(far.x, min(far.y, far.z));
#if ESTIMATOR == ESTIMATOR_BASELINE
  // The tutorial: a hit closer than 0.05 is ignored and the exit point used instead.
  const float EPSILON = 5e-2;
  if (t_near >= t_far) return false;
  float chosen = t_near > EPSILON ? t_near : t_far;
  if (chosen < EPSILON || t_near > t_max) return false;
  t = chosen;
  face = axis * 2 + (inv[axis] > 0.0 ? 1 : 0);
  return true;
#endif
  if (!(t_near > 0.0 && t_near < t_far && t_near < t_max)) return false;
  t = t_near;
  face = axis * 2 + (inv[axis] > 0.0 ? 1 : 0);  // entering along +axis means the face looks along -axis
  return true;
}

struct Hit {
  float t;
  int box;   // -1: nothing
  int face;
};

Hit trace(vec3 origin, vec3 dir, int skip_box) {
  Hit hit = Hit(3.4e38, -1, 0);
  for (int i = 0; i < int(constants.image.w); ++i) {
    float t;
    int face;
    if (i != skip_box && intersect_box(i, origin, dir, hit.t, t, face)) hit = Hit(t, i, face);
  }
  return hit;
}

// True when nothing but the two skipped boxes lies strictly between the segment's ends.
bool visible(vec3 from, vec3 dir, float distance, int skip_a, int skip_b) {
  float t_max = distance * (1.0 - 1.0 / 1048576.0);
  for (int i = 0; i < int(constants.image.w); ++i) {
    float t;
    int face;
    if (i != skip_a && i != skip_b && intersect_box(i, from, dir, t_max, t, face)) return false;
  }
  return true;
}

// The hit point placed exactly on the face plane (in the box frame), so the next ray starts on the
// surface, neither inside nor in front of it.
vec3 surface_point(int box, int face, vec3 p) {
#if ESTIMATOR == ESTIMATOR_BASELINE
  return p;  // the tutorial starts the next ray at the computed hit point
#endif
  vec3 local = to_local(box, p - scene.boxes[box].center.xyz);
  int axis = face / 2;
  local[axis] = (face % 2 == 1) ? -scene.boxes[box].half_size[axis] : scene.boxes[box].half_size[axis];
  return scene.boxes[box].center.xyz + to_world(box, local);
}

vec3 emitted(int box, int face) {
  int emitting = int(scene.boxes[box].emittance.w);
  return (emitting == face || emitting == 6) ? scene.boxes[box].emittance.rgb : vec3(0.0);
}

// The primary ray through the centre of pixel (x, y), y down.
vec3 primary_direction(vec2 pixel_centre) {
  // A traced pixel stands for a divisor x divisor block of the full image: its ray goes through the
  // block's centre (with divisor 1, exactly the pixel's own centre).
  const uvec2 full = uvec2(constants.light.w & 0xFFFFu, constants.light.w >> 16);
  vec2 ndc = pixel_centre * float(constants.light.z) / vec2(full) * 2.0 - 1.0;
  return normalize(constants.camera_forward.xyz + ndc.x * constants.camera_right.xyz -
                   ndc.y * constants.camera_up.xyz);
}
