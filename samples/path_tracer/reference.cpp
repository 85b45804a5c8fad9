// Mirrors shaders/path_tracer/{scene.glsl,path_trace.comp} in double precision; keep them in step.
#include "reference.hpp"

#include <algorithm>
#include <cmath>

#include "random.hpp"
#include "statepack/bootstrap/host_tools.hpp"

namespace statepack::path_tracer {
namespace {

constexpr double kPi = 3.14159265358979323846;

struct V3 {
  double x = 0, y = 0, z = 0;
  double& operator[](int i) { return i == 0 ? x : i == 1 ? y : z; }
  double operator[](int i) const { return i == 0 ? x : i == 1 ? y : z; }
};
V3 operator+(V3 a, V3 b) {
  return {a.x + b.x, a.y + b.y, a.z + b.z};
}
V3 operator-(V3 a, V3 b) {
  return {a.x - b.x, a.y - b.y, a.z - b.z};
}
V3 operator*(V3 a, double s) {
  return {a.x * s, a.y * s, a.z * s};
}
V3 operator*(V3 a, V3 b) {
  return {a.x * b.x, a.y * b.y, a.z * b.z};
}
double dot(V3 a, V3 b) {
  return a.x * b.x + a.y * b.y + a.z * b.z;
}
V3 normalize(V3 a) {
  return a * (1.0 / std::sqrt(dot(a, a)));
}
V3 from(const Vec3& v) {
  return {v[0], v[1], v[2]};
}

struct Box {
  V3 center, half, albedo, emittance;
  int emitting_face = -1;  // 0..5, 6: every face
  double c = 1, s = 0;
};

// A light without area (scene.hpp's SceneLight), in double precision.
struct DeltaLight {
  SceneLight::Type type = SceneLight::Type::point;
  V3 position, direction, c0;
  double r0 = 1, r_min = 0.01, r_max = 0, cos_umbra = 0, cos_penumbra = 1;
};

struct Hit {
  double t = 1e300;
  int box = -1, face = 0;
};

class Tracer {
 public:
  Tracer(const Scene& scene, const RenderSettings& settings, uint32_t width, uint32_t height)
      : settings_(settings), width_(width), height_(height) {
    uint32_t light = 0;
    for (const GpuBox& g : gpu_boxes(scene, light)) {
      Box b;
      b.center = {g.center[0], g.center[1], g.center[2]};
      b.half = {g.half_size[0], g.half_size[1], g.half_size[2]};
      b.albedo = {g.albedo[0], g.albedo[1], g.albedo[2]};
      b.emittance = {g.emittance[0], g.emittance[1], g.emittance[2]};
      b.emitting_face = int(g.emittance[3]);
      b.c = g.rotation[0], b.s = g.rotation[1];
      boxes_.push_back(b);
    }
    light_ = scene.area_light ? int(light) : -1;
    for (const SceneLight& l : scene.lights) {
      DeltaLight d;
      d.type = l.type;
      d.position = from(l.position), d.direction = from(l.direction);
      d.c0 = from(l.color) * double(l.intensity);
      d.r0 = l.reference_distance, d.r_min = l.radius, d.r_max = l.range;
      constexpr double kDegrees = kPi / 180;
      d.cos_umbra = std::cos(l.umbra_degrees * kDegrees),
      d.cos_penumbra = std::cos(l.penumbra_degrees * kDegrees);
      lights_.push_back(d);
    }
    other_emitters_ = std::any_of(scene.boxes.begin(), scene.boxes.end(), [](const SceneBox& b) {
      return b.emittance[0] > 0 || b.emittance[1] > 0 || b.emittance[2] > 0;
    });
    const CameraBasis basis = camera_basis(scene.camera, width, height);
    auto v3 = [](const std::array<double, 3>& a) { return V3{a[0], a[1], a[2]}; };
    forward_ = v3(basis.forward), right_ = v3(basis.right), up_ = v3(basis.up);
    origin_ = from(scene.camera.position);
  }

  // One sample of pixel (x, y): the same path the GPU traces for that sample index.
  V3 sample(uint32_t px, uint32_t py, uint32_t sample_index) const {
    V3 ndc{(px + 0.5) / width_ * 2 - 1, (py + 0.5) / height_ * 2 - 1, 0};
    V3 dir = normalize(forward_ + right_ * ndc.x - up_ * ndc.y);
    Hit hit = trace(origin_, dir, -1);
    if (hit.box < 0) return {};
    V3 x = surface_point(hit.box, hit.face, origin_ + dir * hit.t);
    int box = hit.box, face = hit.face;
    const bool nee = settings_.next_event_estimation, last_only = settings_.last_bounce_only;
    V3 throughput{1, 1, 1}, radiance = emitted(box, face);
    for (uint32_t j = 0; j < settings_.bounces; ++j) {
      if (last_only) radiance = {};
      auto w = pcg4d({px, py, sample_index, settings_.seed + j * 0x9E3779B9u});
      double u[4];
      for (int i = 0; i < 4; ++i) u[i] = double(to_unit(w[i]));
      V3 n = normal(box, face);
      V3 rho = boxes_[box].albedo;
      if (nee && light_ >= 0)
        radiance = radiance + throughput * rho * (1 / kPi) * light_sample(x, n, box, u[0], u[1]);
      for (const DeltaLight& l : lights_) radiance = radiance + throughput * rho * delta_light(l, x, n, box);
      if (nee && j + 1 == settings_.bounces && !other_emitters_) break;
      V3 d = cosine_direction(n, u[2], u[3]);
      throughput = throughput * rho;
      Hit next = trace(x, d, box);
      if (next.box < 0) break;
      x = surface_point(next.box, next.face, x + d * next.t);
      box = next.box, face = next.face;
      if (!nee || box != light_) radiance = radiance + throughput * emitted(box, face);
    }
    return radiance;
  }

 private:
  V3 rotate(V3 v, double c, double s) const { return {c * v.x - s * v.z, v.y, s * v.x + c * v.z}; }
  V3 to_local(int i, V3 v) const { return rotate(v, boxes_[i].c, -boxes_[i].s); }
  V3 to_world(int i, V3 v) const { return rotate(v, boxes_[i].c, boxes_[i].s); }
  static V3 face_normal_local(int face) {
    V3 n;
    n[face / 2] = face % 2 == 1 ? -1 : 1;
    return n;
  }
  V3 normal(int box, int face) const { return to_world(box, face_normal_local(face)); }
  V3 emitted(int box, int face) const {
    const Box& b = boxes_[box];
    return (b.emitting_face == face || b.emitting_face == 6) ? b.emittance : V3{};
  }

  bool intersect(int i, V3 origin, V3 dir, double t_max, double& t, int& face) const {
    const Box& b = boxes_[i];
    V3 o = to_local(i, origin - b.center), d = to_local(i, dir), inv;
    for (int a = 0; a < 3; ++a) {
      double m = std::max(std::abs(d[a]), 1e-20);
      inv[a] = d[a] < 0 ? -1 / m : 1 / m;
    }
    V3 near, far;
    for (int a = 0; a < 3; ++a) {
      double t1 = (-b.half[a] - o[a]) * inv[a], t2 = (b.half[a] - o[a]) * inv[a];
      near[a] = std::min(t1, t2), far[a] = std::max(t1, t2);
    }
    int axis = 0;
    double t_near = near.x;
    if (near.y > t_near) axis = 1, t_near = near.y;
    if (near.z > t_near) axis = 2, t_near = near.z;
    double t_far = std::min(far.x, std::min(far.y, far.z));
    if (!(t_near > 0 && t_near < t_far && t_near < t_max)) return false;
    t = t_near;
    face = axis * 2 + (inv[axis] > 0 ? 1 : 0);
    return true;
  }

  Hit trace(V3 origin, V3 dir, int skip) const {
    Hit hit;
    for (int i = 0; i < int(boxes_.size()); ++i) {
      double t;
      int face;
      if (i != skip && intersect(i, origin, dir, hit.t, t, face)) hit = {t, i, face};
    }
    return hit;
  }

  bool visible(V3 from, V3 dir, double distance, int skip_a, int skip_b) const {
    const double t_max = distance * (1.0 - 1.0 / 1048576.0);
    for (int i = 0; i < int(boxes_.size()); ++i) {
      double t;
      int face;
      if (i != skip_a && i != skip_b && intersect(i, from, dir, t_max, t, face)) return false;
    }
    return true;
  }

  V3 surface_point(int box, int face, V3 p) const {
    V3 local = to_local(box, p - boxes_[box].center);
    int axis = face / 2;
    local[axis] = face % 2 == 1 ? -boxes_[box].half[axis] : boxes_[box].half[axis];
    return boxes_[box].center + to_world(box, local);
  }

  V3 light_sample(V3 x, V3 n, int source, double u0, double u1) const {
    const Box& b = boxes_[light_];
    const int face = b.emitting_face, axis = face / 2, a1 = (axis + 1) % 3, a2 = (axis + 2) % 3;
    V3 local = face_normal_local(face) * b.half;
    local[a1] = (2 * u0 - 1) * b.half[a1];
    local[a2] = (2 * u1 - 1) * b.half[a2];
    V3 y = b.center + to_world(light_, local);
    V3 light_normal = normal(light_, face);
    const double area = 4 * b.half[a1] * b.half[a2];
    V3 to_light = y - x;
    const double d2 = dot(to_light, to_light);
    if (d2 < 1e-12) return {};
    const double d = std::sqrt(d2);
    V3 l = to_light * (1 / d);
    const double cos_x = dot(n, l), cos_light = -dot(light_normal, l);
    if (cos_x <= 0 || cos_light <= 0 || !visible(x, l, d, source, light_)) return {};
    return b.emittance * (cos_x * cos_light * area / d2);
  }

  // c(r) * cos(theta_x) of a light without area at x, visibility included (shaders/path_tracer/lights.glsl
  // returns pi times this; the caller there divides by pi with the albedo).
  V3 delta_light(const DeltaLight& l, V3 x, V3 n, int source) const {
    V3 dir;
    double distance = 1e30, scale = 1;
    if (l.type == SceneLight::Type::directional) {
      dir = l.direction * -1.0;
    } else {
      V3 to_light = l.position - x;
      distance = std::sqrt(dot(to_light, to_light));
      if (!(distance > 0)) return {};
      dir = to_light * (1 / distance);
      const double q = l.r0 / std::max(distance, l.r_min);
      scale = q * q;
      if (l.r_max > 0) {
        const double w = std::max(1 - std::pow(distance / l.r_max, 4), 0.0);
        scale *= w * w;
      }
      if (l.type == SceneLight::Type::spot) {
        const double t = std::clamp(
            (dot(l.direction, dir * -1.0) - l.cos_umbra) / (l.cos_penumbra - l.cos_umbra), 0.0, 1.0);
        scale *= t * t * (3 - 2 * t);
      }
    }
    const double cos_x = dot(n, dir);
    if (cos_x <= 0 || scale <= 0 || !visible(x, dir, distance, source, -1)) return {};
    return l.c0 * (scale * cos_x);
  }

  static V3 cosine_direction(V3 n, double u0, double u1) {
    const double phi = 2 * kPi * (u0 - 0.5), r = std::sqrt(u1);
    V3 local{r * std::cos(phi), r * std::sin(phi), std::sqrt(std::max(0.0, 1 - u1))};
    const double s = n.z >= 0 ? 1 : -1, a = -1 / (s + n.z), b = n.x * n.y * a;
    V3 t{1 + s * n.x * n.x * a, s * b, -s * n.x}, bt{b, s + n.y * n.y * a, -n.y};
    return normalize(t * local.x + bt * local.y + n * local.z);
  }

  std::vector<Box> boxes_;
  std::vector<DeltaLight> lights_;
  int light_ = 0;  // -1: no rectangular light
  bool other_emitters_ = false;
  RenderSettings settings_;
  uint32_t width_, height_;
  V3 origin_, forward_, right_, up_;
};

}  // namespace

ReferenceImage render_reference(const Scene& scene, const RenderSettings& settings, uint32_t width,
                                uint32_t height, uint32_t spp, uint32_t threads) {
  ReferenceImage out;
  out.width = width, out.height = height, out.samples = spp;
  out.mean.assign(size_t(width) * height * 3, 0.0);
  out.variance.assign(size_t(width) * height * 3, 0.0);
  const Tracer tracer(scene, settings, width, height);
  // Rows on statepack's one thread pool (bootstrap::parallel_for), each row's pixels in order.
  statepack::bootstrap::parallel_for(height, threads, [&](size_t row) {
    const uint32_t y = uint32_t(row);
    for (uint32_t x = 0; x < width; ++x) {
      double sum[3] = {}, sum2[3] = {};
      for (uint32_t s = 0; s < spp; ++s) {
        V3 v = tracer.sample(x, y, s);
        for (int c = 0; c < 3; ++c) sum[c] += v[c], sum2[c] += v[c] * v[c];
      }
      for (int c = 0; c < 3; ++c) {
        const size_t i = (size_t(y) * width + x) * 3 + c;
        out.mean[i] = sum[c] / spp;
        out.variance[i] = spp > 1 ? std::max(0.0, (sum2[c] - sum[c] * sum[c] / spp) / (spp - 1)) : 0.0;
      }
    }
  });
  return out;
}

}  // namespace statepack::path_tracer
