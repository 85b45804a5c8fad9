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

struct Camera {
  Vec3 position{0, 1, -20};
  float yaw_degrees = 0, pitch_degrees = 0, fov_degrees = 45;
};

struct Scene {
  std::vector<SceneBox> boxes;
  Light light;
  Camera camera;
};

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
// Boxes first, the light last; `light_index` receives the light's position.
std::vector<GpuBox> gpu_boxes(const Scene& scene, uint32_t& light_index);

}  // namespace statepack::path_tracer
