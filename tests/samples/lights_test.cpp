// The lights without area (directional, point, spot) against their formulas (docs/path_tracer.md,
// "Lights"), rendered by the path tracer on lavapipe with validation on: one bounce over a Lambertian
// floor seen from above, where a delta light's contribution is exact (no random choice reaches it), so
// every pixel is compared with the closed form at the point it sees.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iterator>
#include <string>
#include <vector>

#include "common/run_command.hpp"
#include "path_tracer/scene.hpp"
#include "pfm_image.hpp"

namespace {

namespace fs = std::filesystem;
using statepack::path_tracer::Camera;
using statepack::path_tracer::camera_basis;

constexpr uint32_t kSize = 17;  // odd: the centre pixel looks straight down at (0, 0, 0)
constexpr double kAlbedo = 0.5, kCameraHeight = 10, kPi = 3.14159265358979323846;

// A floor (top at y = 0, albedo 0.5) seen from straight above, lit by `lights` (a JSON array).
std::string floor_scene(const std::string& lights) {
  return R"({"camera": {"position": [0, 10, 0], "pitch_degrees": -90, "fov_degrees": 60},
    "boxes": [{"name": "Floor", "center": [0, -0.5, 0], "half_size": [50, 0.5, 50], "albedo": [0.5, 0.5, 0.5]}],
    "lights": )" +
         lights + "}";
}

struct Render {
  int exit_code = 0;
  std::string output;
  std::vector<float> rgb;  // rows top to bottom
};

Render render(const std::string& name, const std::string& scene, const std::string& extra = "") {
  const fs::path dir = fs::path(STATEPACK_TEST_OUTPUT_DIR) / "lights";
  fs::create_directories(dir);
  const fs::path scene_path = dir / (name + ".json"), out = dir / (name + ".pfm");
  std::ofstream(scene_path) << scene;
  fs::remove(out);
  auto result = statepack::testing::run_command(
      "'" + std::string(STATEPACK_PATH_TRACER) + "' --headless --scene '" + scene_path.string() +
      "' --out '" + out.string() + "' --width " + std::to_string(kSize) + " --height " +
      std::to_string(kSize) + " --spp 2 --bounces 1 " + extra);
  Render run{result.exit_code, result.output, {}};
  if (result.exit_code == 0) run.rgb = statepack::testing::read_pfm(out).rgb;
  return run;
}

// The floor point pixel (x, y) sees, as the path tracer's primary ray finds it.
std::array<double, 3> floor_point(uint32_t x, uint32_t y) {
  Camera camera;
  camera.position = {0, float(kCameraHeight), 0};
  camera.pitch_degrees = -90;
  camera.fov_degrees = 60;
  const auto b = camera_basis(camera, kSize, kSize);
  const double nx = (x + 0.5) / kSize * 2 - 1, ny = (y + 0.5) / kSize * 2 - 1;
  std::array<double, 3> d;
  for (int i = 0; i < 3; ++i) d[i] = b.forward[i] + nx * b.right[i] - ny * b.up[i];
  const double t = kCameraHeight / -d[1];
  return {d[0] * t, 0.0, d[2] * t};
}

double centre(const Render& run) {
  return run.rgb.at((size_t(kSize / 2) * kSize + kSize / 2) * 3);
}

// Every pixel (red channel) against `expected(point)`, within float's rounding of the formula.
void expect_every_pixel(const Render& run,
                        const std::function<double(const std::array<double, 3>&)>& expected) {
  ASSERT_EQ(run.exit_code, 0) << run.output;
  ASSERT_EQ(run.rgb.size(), size_t(kSize) * kSize * 3);
  size_t wrong = 0;
  std::string first;
  for (uint32_t y = 0; y < kSize; ++y)
    for (uint32_t x = 0; x < kSize; ++x) {
      const double want = expected(floor_point(x, y)), got = run.rgb[(size_t(y) * kSize + x) * 3];
      if (!(std::abs(got - want) <= 2e-4 * std::abs(want) + 1e-6)) {
        if (wrong++ == 0)
          first = "pixel (" + std::to_string(x) + ", " + std::to_string(y) + "): " + std::to_string(got) +
                  ", expected " + std::to_string(want);
      }
    }
  EXPECT_EQ(wrong, 0u) << first;
}

// rho * c0 * (r0 / max(r, r_min))^2 * cos(theta) for a point light at height h above floor point p.
double point_light(const std::array<double, 3>& p, double h, double c0, double r_min = 0.01,
                   double range = 0) {
  const double dx = -p[0], dz = -p[2], r = std::sqrt(dx * dx + h * h + dz * dz);
  double scale = std::pow(1.0 / std::max(r, r_min), 2);
  if (range > 0) scale *= std::pow(std::max(1 - std::pow(r / range, 4), 0.0), 2);
  return kAlbedo * c0 * scale * (h / r);
}

TEST(Lights, PointLightFollowsTheInverseSquare) {
  const auto lamp = [](double h) {
    return R"([{"name": "Lamp", "type": "point", "position": [0, )" + std::to_string(h) +
           R"(, 0], "intensity": 4}])";
  };
  const Render near = render("point_2", floor_scene(lamp(2))), far = render("point_4", floor_scene(lamp(4)));
  expect_every_pixel(near, [](const auto& p) { return point_light(p, 2, 4); });
  expect_every_pixel(far, [](const auto& p) { return point_light(p, 4, 4); });
  ASSERT_FALSE(near.rgb.empty() || far.rgb.empty());
  EXPECT_NEAR(centre(near) / centre(far), 4.0, 1e-4) << "heights h and 2h";
}

TEST(Lights, ClampedNearTheLightAndWindowedAtItsRange) {
  // Below r_min the colour stays that of r_min: heights 0.2 and 0.4 under radius 0.5 light the point
  // below alike.
  const auto clamped = [](double h) {
    return R"([{"name": "Bulb", "type": "point", "position": [0, )" + std::to_string(h) +
           R"(, 0], "intensity": 4, "radius": 0.5}])";
  };
  const Render low = render("clamp_low", floor_scene(clamped(0.2))),
               high = render("clamp_high", floor_scene(clamped(0.4)));
  expect_every_pixel(low, [](const auto& p) { return point_light(p, 0.2, 4, 0.5); });
  expect_every_pixel(high, [](const auto& p) { return point_light(p, 0.4, 4, 0.5); });
  ASSERT_FALSE(low.rgb.empty() || high.rgb.empty());
  EXPECT_NEAR(centre(low), kAlbedo * 4 / 0.25, 1e-3);
  EXPECT_NEAR(centre(low), centre(high), 1e-4 * centre(low));
  // A range of 3 at height 2: the window max(1 - (r/3)^4, 0)^2 against the same light without one, and
  // nothing beyond the range.
  const Render windowed =
      render("window", floor_scene(R"([{"name": "Lamp", "type": "point", "position": [0, 2, 0],
    "intensity": 4, "range": 3}])"));
  expect_every_pixel(windowed, [](const auto& p) { return point_light(p, 2, 4, 0.01, 3); });
  ASSERT_FALSE(windowed.rgb.empty());
  EXPECT_NEAR(centre(windowed), point_light({0, 0, 0}, 2, 4) * std::pow(1 - std::pow(2.0 / 3, 4), 2), 1e-4);
  EXPECT_EQ(windowed.rgb[0], 0.0f) << "a corner lies beyond the range";
}

TEST(Lights, SpotIsThePointLightInsideItsPenumbraBlackOutsideItsUmbraSmoothBetween) {
  const double umbra = 40, penumbra = 20, cos_u = std::cos(umbra * kPi / 180),
               cos_p = std::cos(penumbra * kPi / 180);
  const Render spot = render("spot", floor_scene(R"([{"name": "Spot", "type": "spot", "position": [0, 2, 0],
    "direction": [0, -1, 0], "intensity": 4, "umbra_degrees": 40, "penumbra_degrees": 20}])"));
  size_t inside = 0, between = 0, outside = 0;
  expect_every_pixel(spot, [&](const auto& p) {
    const double r = std::sqrt(p[0] * p[0] + 4 + p[2] * p[2]), cos_s = 2 / r;
    const double t = std::clamp((cos_s - cos_u) / (cos_p - cos_u), 0.0, 1.0);
    (t == 1 ? inside : t == 0 ? outside : between)++;
    return point_light(p, 2, 4) * t * t * (3 - 2 * t);
  });
  // The image covers all three parts of the cone.
  EXPECT_GT(inside, 0u);
  EXPECT_GT(between, 0u);
  EXPECT_GT(outside, 0u);
}

TEST(Lights, DirectionalLightGivesTheCosineOfItsTilt) {
  const Render down =
      render("sun_down", floor_scene(R"([{"name": "Sun", "type": "directional", "direction": [0, -1, 0],
    "intensity": 3}])"));
  const Render tilted = render("sun_tilted", floor_scene(R"([{"name": "Sun", "type": "directional",
    "direction": [0.5, -0.8660254037844386, 0], "intensity": 3}])"));
  expect_every_pixel(down, [](const auto&) { return kAlbedo * 3; });
  expect_every_pixel(tilted, [](const auto&) { return kAlbedo * 3 * std::cos(kPi / 6); });
}

// Hard cases: a light on the surface, at the very point a pixel sees (r = 0), and a range just above r.
TEST(Lights, HardCasesStayFinite) {
  const Render on_floor =
      render("on_floor",
             floor_scene(R"([{"name": "Flat", "type": "point", "position": [0, 0, 0], "intensity": 4}])"));
  expect_every_pixel(on_floor,
                     [](const auto&) { return 0.0; });  // in the floor's plane: cos = 0, or no direction
  const Render edge =
      render("range_edge", floor_scene(R"([{"name": "Lamp", "type": "point", "position": [0, 2, 0],
    "intensity": 4, "range": 2.0001}])"));
  expect_every_pixel(edge, [](const auto& p) { return point_light(p, 2, 4, 0.01, 2.0001); });
  const Render grazing =
      render("grazing", floor_scene(R"([{"name": "Spot", "type": "spot", "position": [0, 0.001, 0],
    "direction": [1, 0, 0], "intensity": 4, "umbra_degrees": 90, "penumbra_degrees": 89.9}])"));
  ASSERT_EQ(grazing.exit_code, 0) << grazing.output;
  for (float v : grazing.rgb) EXPECT_TRUE(std::isfinite(v) && v >= 0) << v;
}

// The sample scene with every kind of light renders finite, and each light adds light: without it the
// image's mean is lower.
TEST(Lights, TheSampleSceneWithEveryKindRendersAndEachLightCounts) {
  const fs::path sample = fs::path(STATEPACK_DEFAULT_SCENE).parent_path() / "cornell_box_lights.json";
  std::ifstream in(sample);
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  ASSERT_FALSE(text.empty()) << sample;
  auto mean = [](const Render& r) {
    double sum = 0;
    for (float v : r.rgb) sum += v;
    return sum / double(r.rgb.size());
  };
  const Render all = render("sample_all", text);
  ASSERT_EQ(all.exit_code, 0) << all.output;
  for (float v : all.rgb) ASSERT_TRUE(std::isfinite(v) && v >= 0) << v;
  for (const char* name : {"Lamp", "Spot", "Sun"}) {
    // The same scene with that light's intensity a millionth: what it gave is gone.
    const std::string key = std::string("\"name\": \"") + name + "\"";
    const size_t at = text.find(key), intensity = text.find("\"intensity\": ", at);
    ASSERT_NE(at, std::string::npos) << name;
    std::string dimmed = text;
    dimmed.insert(text.find_first_of(", }", intensity + 13), "e-6");
    const Render without = render(std::string("sample_without_") + name, dimmed);
    ASSERT_EQ(without.exit_code, 0) << without.output;
    EXPECT_LT(mean(without), mean(all) * 0.995) << name << " adds nothing";
  }
}

// Many lights are a legitimate scene (no count limit): 300 identical point lamps at one place light the
// floor 300 times as much as one does, with either choice among them.
TEST(Lights, ManyLightsAddUp) {
  std::string many = "[";
  for (int i = 0; i < 300; ++i)
    many += std::string(i ? "," : "") + R"({"type": "point", "position": [0, 2, 0], "intensity": 0.01})";
  many += "]";
  const Render all = render("many_all", floor_scene(many));
  expect_every_pixel(all, [](const auto& p) { return 300 * point_light(p, 2, 0.01); });
  // One chosen per vertex among equal lights: each has probability 1/300 and is multiplied by 300.
  const Render one = render("many_one", floor_scene(many), "--delta-lights one");
  expect_every_pixel(one, [](const auto& p) { return 300 * point_light(p, 2, 0.01); });
}

// A bad light is the scene's error, naming the light and the key (exit 1, nothing rendered).
TEST(Lights, BadLightsAreSceneErrorsNamingTheLightAndKey) {
  struct Case {
    const char* light;
    const char* message;
  };
  const Case cases[] = {
      {R"({"name": "Lamp", "type": "point", "position": [0, 2, 0], "intensity": 0})",
       "light 'Lamp': 'intensity' must be above 0 (a light that gives none) [/lights/0/intensity]"},
      {R"({"name": "Lamp", "type": "point", "position": [0, 2, 0], "range": 0})",
       "light 'Lamp': 'range' must be above 0 (leave it out for no window) [/lights/0/range]"},
      {R"({"name": "Cone", "type": "spot", "position": [0, 2, 0], "direction": [0, -1, 0], "umbra_degrees": 20, "penumbra_degrees": 20})",
       "light 'Cone': 'umbra_degrees' must be larger than 'penumbra_degrees'"},
      {R"({"name": "Sun", "type": "directional", "direction": [0, 0, 0]})",
       "light 'Sun': 'direction' must not be zero [/lights/0/direction]"},
      {R"({"name": "Far", "type": "point", "position": [0, 1e39, 0]})",
       "must be a number from -1e6 to 1e6 [/lights/0/position/1]"},
      {R"({"name": "Lamp", "type": "torch", "position": [0, 2, 0]})",
       "light 'Lamp': 'type' must be \"directional\", \"point\" or \"spot\" [/lights/0/type]"},
      {R"({"type": "point"})", "lights/0: a point light needs 'position' [/lights/0/position]"},
      {R"({"name": "Sun", "type": "directional", "direction": [0, -1, 0], "position": [0, 1, 0]})",
       "unknown key 'position' [/lights/0/position]"},
  };
  for (const Case& c : cases) {
    const Render run = render("bad", floor_scene(std::string("[") + c.light + "]"));
    EXPECT_EQ(run.exit_code, 1) << c.light << "\n" << run.output;
    EXPECT_NE(run.output.find(c.message), std::string::npos) << c.light << "\n" << run.output;
  }
  const Render none = render("no_light", R"({"boxes": [{"center": [0, 0, 0], "half_size": [1, 1, 1]}]})");
  EXPECT_EQ(none.exit_code, 1);
  EXPECT_NE(none.output.find("the scene needs a 'light' (the rectangle) or a non-empty 'lights' [/light]"),
            std::string::npos)
      << none.output;
}

}  // namespace
