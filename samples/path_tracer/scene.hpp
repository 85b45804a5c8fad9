// The scene as data: axis-aligned boxes with an optional rotation about their vertical axis, and one
// rectangular light (the bottom face of a thin box). Nothing more general than the Cornell box needs.
#pragma once

#include <array>
#include <filesystem>
#include <string>
#include <vector>

#include "statepack/result.hpp"

namespace statepack::path_tracer {

using Vec3 = std::array<float, 3>;

struct SceneBox {
  std::string name;
  Vec3 center{}, half_size{1, 1, 1}, albedo{0.5f, 0.5f, 0.5f};
  Vec3 emittance{};  // radiance leaving every face (found by bounces; only the light is sampled)
  float rotation_degrees = 0;
};

struct Light {
  Vec3 center{0, 4.9f, 0}, half_size{1.5f, 0.02f, 1.5f}, albedo{0.75f, 0.75f, 0.75f}, color{1, 1, 1};
  float intensity = 15;  // radiance of the bottom face = color * intensity
};

// A light without area: directional, point or spot. Only next-event estimation finds it (a bounce never
// hits a point). Its colour at distance r is c0 * (r0 / max(r, r_min))^2, times a window that reaches
// zero at `range`, times a smoothstep between the umbra and penumbra angles for a spot
// (docs/path_tracer.md, "Lights"); a white Lambertian surface facing it reflects that colour.
struct SceneLight {
  enum class Type : uint32_t { directional = 0, point = 1, spot = 2 };
  std::string name;
  Type type = Type::point;
  Vec3 color{1, 1, 1};
  float intensity = 1;           // c0 = color * intensity, the colour at reference_distance
  Vec3 position{};               // point and spot
  Vec3 direction{0, -1, 0};      // directional: the way its light travels; spot: the way it points
  float reference_distance = 1;  // r0
  float radius = 0.01f;          // r_min: closer points get the colour at r_min (no infinity at r = 0)
  float range = 0;               // r_max: 0 for none (no window)
  float umbra_degrees = 45, penumbra_degrees = 30;  // spot: from its axis to the dark edge / the full light
};
// Bit (1 << type) for each kind of light a scene has: what the path-tracing pipeline is specialised for.
inline constexpr uint32_t kDirectionalLights = 1, kPointLights = 2, kSpotLights = 4;

struct Camera {
  Vec3 position{0, 1, -20};
  float yaw_degrees = 0, pitch_degrees = 0, fov_degrees = 45;
};

struct Scene {
  std::vector<SceneBox> boxes;
  Light light;
  bool area_light = true;  // the rectangle above; a scene file without "light" has none
  std::vector<SceneLight> lights;
  Camera camera;
};
// kDirectionalLights | kPointLights | kSpotLights for the kinds `scene.lights` holds.
uint32_t light_kinds(const Scene& scene);

// The camera's view basis for an image of width x height: `right` and `up` are scaled by the tangent of
// half the field of view (and `right` by the aspect), so pixel centre (x, y) looks along
// forward + ndc_x * right - ndc_y * up. Shared by the GPU constants and the CPU reference.
struct CameraBasis {
  std::array<double, 3> forward, right, up;
};
CameraBasis camera_basis(const Camera& camera, uint32_t width, uint32_t height);

// Reads a scene file; errors name the file and the JSON pointer of the bad value.
Result<Scene> load_scene(const std::filesystem::path& path);

// The GPU layout of one box (std430, 80 bytes), matching `Box` in shaders/path_tracer/scene.glsl.
struct GpuBox {
  float center[4], half_size[4], albedo[4], emittance[4], rotation[4];
};
// Boxes first, the rectangular light last; `light_index` receives its position (UINT32_MAX: none).
std::vector<GpuBox> gpu_boxes(const Scene& scene, uint32_t& light_index);
// The lights without area in the same 80-byte records, read by `delta_light` in
// shaders/path_tracer/lights.glsl: center = position, type; half_size = c0 rgb, r0; albedo = r_min,
// r_max (0: none), cos(umbra), 1 / (cos(penumbra) - cos(umbra)); emittance = unit direction.
std::vector<GpuBox> gpu_lights(const Scene& scene);

}  // namespace statepack::path_tracer
