#version 450
// G-buffer: one primary ray per pixel centre. Float targets keep the primary hit exact (8-bit albedo
// and normals would bias grey surfaces by +0.39 % and tilt normals); depth holds the hit distance.
#extension GL_GOOGLE_include_directive : require
#include "scene.glsl"

layout(location = 0) out vec4 out_albedo;     // rgb albedo, a: box index + 1 (0: nothing hit)
layout(location = 1) out vec4 out_normal;     // xyz unit normal, w: face index
layout(location = 2) out vec4 out_emittance;  // rgb radiance emitted toward the camera
layout(location = 3) out float out_depth;     // hit distance along the primary ray, -1: nothing

void main() {
  vec3 dir = primary_direction(gl_FragCoord.xy);
  Hit hit = trace(constants.camera_position.xyz, dir, -1);
  if (hit.box < 0) {
    out_albedo = vec4(0.0);
    out_normal = vec4(0.0);
    out_emittance = vec4(0.0);
    out_depth = -1.0;
    return;
  }
  out_albedo = vec4(scene.boxes[hit.box].albedo.rgb, float(hit.box + 1));
  out_normal = vec4(box_normal(hit.box, hit.face), float(hit.face));
  out_emittance = vec4(emitted(hit.box, hit.face), 0.0);
  out_depth = hit.t;
}
