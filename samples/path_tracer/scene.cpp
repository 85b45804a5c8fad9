#include "scene.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <nlohmann/json.hpp>

#include "statepack/bootstrap/host_tools.hpp"

namespace statepack::path_tracer {
namespace {

using nlohmann::json;

constexpr float kMaxCoordinate = 1e6f;
// Radiance far above any light keeps every sum of path contributions finite in float.
constexpr float kMaxRadiance = 1e6f;
// Angles in degrees: many turns either way, well within float's exact steps of a degree.
constexpr float kMaxAngle = 36000.0f;

struct Reader {
  std::string file;
  std::string problem;

  void fail(const std::string& pointer, const std::string& message) {
    if (problem.empty()) problem = file + ": " + message + " [" + pointer + "]";
  }
  void keys(const json& j, const std::string& pointer, std::initializer_list<const char*> allowed) {
    for (const auto& [key, value] : j.items())
      if (std::none_of(allowed.begin(), allowed.end(), [&](const char* a) { return key == a; }))
        fail(pointer + "/" + key, "unknown key '" + key + "'");
  }
  void vec3(const json& j, const char* key, const std::string& pointer, Vec3& out, bool positive = false) {
    auto it = j.find(key);
    if (it == j.end()) return;
    if (!it->is_array() || it->size() != 3)
      return fail(pointer + "/" + key, std::string("'") + key + "' must be [x, y, z]");
    for (size_t i = 0; i < 3; ++i) {
      if (!(*it)[i].is_number())
        return fail(pointer + "/" + key + "/" + std::to_string(i), "must be a number");
      out[i] = (*it)[i].get<float>();
      // Far beyond any room, float intersection distances overflow: bounded like the scene needs.
      if (!std::isfinite(out[i]) || std::fabs(out[i]) > kMaxCoordinate || (positive && out[i] <= 0))
        return fail(pointer + "/" + key + "/" + std::to_string(i),
                    positive ? "must be a positive number up to 1e6" : "must be a number from -1e6 to 1e6");
    }
  }
  // A number within [low, high] (finite: NaN and infinities cannot be written in JSON, but a double
  // beyond float's range becomes one).
  void number(const json& j, const char* key, const std::string& pointer, float& out, float low, float high) {
    auto it = j.find(key);
    if (it == j.end()) return;
    if (!it->is_number() || !std::isfinite(it->get<float>()) || it->get<float>() < low ||
        it->get<float>() > high)
      return fail(pointer + "/" + key, "must be a number from " + shortest(low) + " to " + shortest(high));
    out = it->get<float>();
  }
  static std::string shortest(float v) {  // 1e6, not 1e+06
    char text[32];
    std::snprintf(text, sizeof text, "%g", double(v));
    std::string s = text;
    if (auto e = s.find("e+0"); e != std::string::npos) s.replace(e, 3, "e");
    return s;
  }
  void albedo(const std::string& pointer, const Vec3& a) {
    for (float c : a)
      if (c < 0 || c > 1) return fail(pointer + "/albedo", "albedo components must be within [0, 1]");
  }
};

// A unit vector from `v`; false for a zero (or denormal) one.
bool normalized(Vec3& v) {
  const double length = std::sqrt(double(v[0]) * v[0] + double(v[1]) * v[1] + double(v[2]) * v[2]);
  if (!(length > 1e-20)) return false;
  for (float& c : v) c = float(c / length);
  return true;
}

// One entry of "lights": every key checked, the message naming the light and the key.
void read_light(Reader& r, const json& l, const std::string& p, SceneLight& light) {
  if (!l.is_object()) return r.fail(p, "a light must be an object");
  if (l.contains("name") && l["name"].is_string()) light.name = l["name"];
  const std::string who = light.name.empty() ? p.substr(1) : "light '" + light.name + "'";
  auto type = l.find("type");
  if (type == l.end() || !type->is_string() ||
      (*type != "directional" && *type != "point" && *type != "spot"))
    return r.fail(p + "/type", who + ": 'type' must be \"directional\", \"point\" or \"spot\"");
  light.type = *type == "directional" ? SceneLight::Type::directional
               : *type == "point"     ? SceneLight::Type::point
                                      : SceneLight::Type::spot;
  const bool directional = light.type == SceneLight::Type::directional;
  const bool spot = light.type == SceneLight::Type::spot;
  if (directional)
    r.keys(l, p, {"name", "type", "color", "intensity", "direction"});
  else if (spot)
    r.keys(l, p,
           {"name", "type", "color", "intensity", "position", "direction", "reference_distance", "radius",
            "range", "umbra_degrees", "penumbra_degrees"});
  else
    r.keys(l, p, {"name", "type", "color", "intensity", "position", "reference_distance", "radius", "range"});
  auto need = [&](const char* key) {
    if (!l.contains(key))
      r.fail(p + "/" + key, who + ": a " + type->get<std::string>() + " light needs '" + key + "'");
  };
  r.vec3(l, "color", p, light.color);
  for (size_t i = 0; i < 3; ++i)
    if (light.color[i] < 0)
      r.fail(p + "/color/" + std::to_string(i), who + ": colour components must be 0 or more");
  r.number(l, "intensity", p, light.intensity, 0, kMaxRadiance);
  if (!(light.intensity > 0))
    r.fail(p + "/intensity", who + ": 'intensity' must be above 0 (a light that gives none)");
  for (size_t i = 0; i < 3; ++i)
    if (double(light.color[i]) * light.intensity > kMaxRadiance)
      r.fail(p + "/color/" + std::to_string(i), who + ": colour x intensity must be at most 1e6");
  if (directional || spot) {
    need("direction");
    r.vec3(l, "direction", p, light.direction);
    if (!normalized(light.direction)) r.fail(p + "/direction", who + ": 'direction' must not be zero");
  }
  if (directional) return;
  need("position");
  r.vec3(l, "position", p, light.position);
  r.number(l, "reference_distance", p, light.reference_distance, 0, kMaxCoordinate);
  if (!(light.reference_distance > 0))
    r.fail(p + "/reference_distance", who + ": 'reference_distance' must be above 0");
  r.number(l, "radius", p, light.radius, 0, kMaxCoordinate);
  if (!(light.radius > 0))
    r.fail(p + "/radius", who + ": 'radius' must be above 0 (it bounds 1 / r^2 near the light)");
  if (l.contains("range")) {
    r.number(l, "range", p, light.range, 0, kMaxCoordinate);
    if (!(light.range > 0))
      r.fail(p + "/range", who + ": 'range' must be above 0 (leave it out for no window)");
  }
  if (!spot) return;
  need("umbra_degrees");
  need("penumbra_degrees");
  r.number(l, "umbra_degrees", p, light.umbra_degrees, 0, 180);
  r.number(l, "penumbra_degrees", p, light.penumbra_degrees, 0, 180);
  if (!(light.umbra_degrees > light.penumbra_degrees))
    r.fail(p + "/umbra_degrees",
           who +
               ": 'umbra_degrees' must be larger than 'penumbra_degrees' (the light fades "
               "from the penumbra angle out to the umbra angle)");
}

void read_lights(Reader& r, const json& lights, Scene& scene) {
  if (!lights.is_array()) return r.fail("/lights", "'lights' must be an array");
  // No count limit: the scene file's 1 MiB bound already bounds it, and the cost is linear in it.
  for (size_t i = 0; i < lights.size(); ++i) {
    SceneLight light;
    read_light(r, lights[i], "/lights/" + std::to_string(i), light);
    scene.lights.push_back(light);
  }
}

}  // namespace

Result<Scene> load_scene(const std::filesystem::path& path) {
  // Bounded and non-blocking: a scene is a few KiB; FIFOs, devices and directories are refused.
  auto file = bootstrap::read_file(path, 1u << 20);
  if (!file) return file.error();
  json root;
  try {
    root = json::parse(file->begin(), file->end());
  } catch (const json::exception& e) {  // syntax errors, and numbers beyond a double (out_of_range)
    return Error{ErrorCode::invalid_argument, path.string() + ": invalid JSON: " + e.what()};
  }
  Reader r{path.string(), ""};
  Scene scene;
  if (!root.is_object())
    return Error{ErrorCode::invalid_argument, path.string() + ": the scene must be a JSON object"};
  r.keys(root, "", {"description", "camera", "boxes", "light", "lights"});
  if (auto c = root.find("camera"); c != root.end()) {
    r.keys(*c, "/camera", {"position", "yaw_degrees", "pitch_degrees", "fov_degrees"});
    r.vec3(*c, "position", "/camera", scene.camera.position);
    r.number(*c, "yaw_degrees", "/camera", scene.camera.yaw_degrees, -kMaxAngle, kMaxAngle);
    r.number(*c, "pitch_degrees", "/camera", scene.camera.pitch_degrees, -90, 90);
    r.number(*c, "fov_degrees", "/camera", scene.camera.fov_degrees, -kMaxAngle, kMaxAngle);
    if (scene.camera.fov_degrees <= 1 || scene.camera.fov_degrees >= 179)
      r.fail("/camera/fov_degrees", "must be in (1, 179)");
  }
  auto boxes = root.find("boxes");
  if (boxes == root.end() || !boxes->is_array() || boxes->empty())
    r.fail("/boxes", "'boxes' must be a non-empty array");
  else {
    for (size_t i = 0; i < boxes->size(); ++i) {
      std::string p = "/boxes/" + std::to_string(i);
      const json& b = (*boxes)[i];
      if (!b.is_object()) {
        r.fail(p, "a box must be an object");
        continue;
      }
      r.keys(b, p, {"name", "center", "half_size", "albedo", "emittance", "rotation_degrees"});
      SceneBox box;
      if (b.contains("name") && b["name"].is_string()) box.name = b["name"];
      if (!b.contains("center") || !b.contains("half_size"))
        r.fail(p, "a box needs 'center' and 'half_size'");
      r.vec3(b, "center", p, box.center);
      r.vec3(b, "half_size", p, box.half_size, true);
      r.vec3(b, "albedo", p, box.albedo);
      r.albedo(p, box.albedo);
      r.vec3(b, "emittance", p, box.emittance);
      for (float e : box.emittance)
        if (e < 0 || e > kMaxRadiance) r.fail(p + "/emittance", "emittance must be from 0 to 1e6");
      r.number(b, "rotation_degrees", p, box.rotation_degrees, -kMaxAngle, kMaxAngle);
      scene.boxes.push_back(box);
    }
  }
  if (auto l = root.find("light"); l != root.end()) {
    r.keys(*l, "/light", {"center", "half_size", "albedo", "color", "intensity"});
    r.vec3(*l, "center", "/light", scene.light.center);
    r.vec3(*l, "half_size", "/light", scene.light.half_size, true);
    r.vec3(*l, "albedo", "/light", scene.light.albedo);
    r.albedo("/light", scene.light.albedo);
    r.vec3(*l, "color", "/light", scene.light.color);
    r.number(*l, "intensity", "/light", scene.light.intensity, 0, kMaxRadiance);
    // Negative light would write negative pixels; the emitted radiance is colour x intensity.
    for (size_t i = 0; i < 3; ++i)
      if (scene.light.color[i] < 0 || double(scene.light.color[i]) * scene.light.intensity > kMaxRadiance)
        r.fail("/light/color/" + std::to_string(i),
               "must be from 0 to 1e6 / intensity (the light's radiance is colour x intensity, at most 1e6)");
  } else {
    scene.area_light = false;
  }
  if (auto lights = root.find("lights"); lights != root.end()) read_lights(r, *lights, scene);
  if (!scene.area_light && scene.lights.empty())
    r.fail("/light", "the scene needs a 'light' (the rectangle) or a non-empty 'lights'");
  if (!r.problem.empty()) return Error{ErrorCode::invalid_argument, r.problem};
  return scene;
}

uint32_t light_kinds(const Scene& scene) {
  uint32_t kinds = 0;
  for (const SceneLight& l : scene.lights) kinds |= 1u << uint32_t(l.type);
  return kinds;
}

CameraBasis camera_basis(const Camera& camera, uint32_t width, uint32_t height) {
  constexpr double kPi = 3.14159265358979323846;
  const double yaw = camera.yaw_degrees * kPi / 180, pitch = camera.pitch_degrees * kPi / 180;
  const double tan_half = std::tan(camera.fov_degrees * kPi / 360), aspect = double(width) / double(height);
  const std::array<double, 3> forward{std::sin(yaw) * std::cos(pitch), std::sin(pitch),
                                      std::cos(yaw) * std::cos(pitch)};
  const std::array<double, 3> right{std::cos(yaw), 0.0, -std::sin(yaw)};
  const std::array<double, 3> up{forward[1] * right[2] - forward[2] * right[1],
                                 forward[2] * right[0] - forward[0] * right[2],
                                 forward[0] * right[1] - forward[1] * right[0]};
  CameraBasis basis{forward, {}, {}};
  for (int i = 0; i < 3; ++i) basis.right[i] = right[i] * tan_half * aspect, basis.up[i] = up[i] * tan_half;
  return basis;
}

std::vector<GpuBox> gpu_boxes(const Scene& scene, uint32_t& light_index) {
  std::vector<GpuBox> out;
  auto add = [&](const Vec3& c, const Vec3& h, const Vec3& a, Vec3 e, float emit_face, float degrees) {
    GpuBox b{};
    const double radians = degrees * 3.14159265358979323846 / 180.0;
    for (int i = 0; i < 3; ++i) {
      b.center[i] = c[i];
      b.half_size[i] = h[i];
      b.albedo[i] = a[i];
      b.emittance[i] = e[i];
    }
    b.emittance[3] = emit_face;
    b.rotation[0] = static_cast<float>(std::cos(radians));
    b.rotation[1] = static_cast<float>(std::sin(radians));
    out.push_back(b);
  };
  constexpr float kEveryFace = 6;
  for (const auto& box : scene.boxes) {
    const bool emits = box.emittance[0] > 0 || box.emittance[1] > 0 || box.emittance[2] > 0;
    add(box.center, box.half_size, box.albedo, box.emittance, emits ? kEveryFace : -1, box.rotation_degrees);
  }
  light_index = UINT32_MAX;
  if (!scene.area_light) return out;
  light_index = static_cast<uint32_t>(out.size());
  const Light& l = scene.light;
  constexpr float kBottomFace = 3;  // face index: axis y (1) * 2 + 1 (outward normal -y)
  add(l.center, l.half_size, l.albedo,
      {l.color[0] * l.intensity, l.color[1] * l.intensity, l.color[2] * l.intensity}, kBottomFace, 0);
  return out;
}

std::vector<GpuBox> gpu_lights(const Scene& scene) {
  std::vector<GpuBox> out;
  constexpr double kDegrees = 3.14159265358979323846 / 180.0;
  for (const SceneLight& l : scene.lights) {
    GpuBox g{};
    for (int i = 0; i < 3; ++i) {
      g.center[i] = l.position[i];
      g.half_size[i] = l.color[i] * l.intensity;
      g.emittance[i] = l.direction[i];
    }
    g.center[3] = float(uint32_t(l.type));
    g.half_size[3] = l.reference_distance;
    g.albedo[0] = l.radius;
    g.albedo[1] = l.range;
    const double cos_umbra = std::cos(l.umbra_degrees * kDegrees),
                 cos_penumbra = std::cos(l.penumbra_degrees * kDegrees);
    g.albedo[2] = float(cos_umbra);
    // Angles a hair apart give a huge but finite slope: the edge is then hard, never NaN.
    g.albedo[3] = float(std::min(1.0 / std::max(cos_penumbra - cos_umbra, 1e-30), 1e30));
    out.push_back(g);
  }
  return out;
}

}  // namespace statepack::path_tracer
