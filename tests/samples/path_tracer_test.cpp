// The path tracer sample, headless on lavapipe with validation on (the program fails on any message):
// finite output, the light's pixels at the light's radiance, red left and green right walls, and the
// same image bit for bit for the same seed.
#include <gtest/gtest.h>
#include <sys/stat.h>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>

#include "common/run_command.hpp"
#include "common/text_files.hpp"
#include "pfm_image.hpp"

#define STB_IMAGE_IMPLEMENTATION
#define STBI_ONLY_PNG
#include <stb/stb_image.h>

namespace {

namespace fs = std::filesystem;

using Image = statepack::testing::PfmImage;
using statepack::testing::read_pfm;

using statepack::testing::read_file;

int run(const std::string& args, std::string& output) {
  auto result =
      statepack::testing::run_command(std::string("'") + STATEPACK_PATH_TRACER + "' --headless " + args);
  output = result.output;
  return result.exit_code;
}

Image render(const std::string& name, const std::string& args) {
  fs::path out = fs::path(STATEPACK_TEST_OUTPUT_DIR) / (name + ".pfm");
  fs::create_directories(out.parent_path());
  std::string output;
  int code = run("--width 64 --height 48 --out '" + out.string() + "' " + args, output);
  EXPECT_EQ(code, 0) << output;
  return read_pfm(out);
}

// Mean colour of a rectangle given in fractions of the image.
std::array<double, 3> mean(const Image& image, double x0, double x1, double y0, double y1) {
  std::array<double, 3> sum{};
  size_t n = 0;
  for (uint32_t y = uint32_t(y0 * image.height); y < uint32_t(y1 * image.height); ++y)
    for (uint32_t x = uint32_t(x0 * image.width); x < uint32_t(x1 * image.width); ++x, ++n)
      for (int c = 0; c < 3; ++c) sum[c] += image.at(x, y)[c];
  for (auto& s : sum) s /= double(n);
  return sum;
}

TEST(PathTracer, ImageIsFiniteAndTheSameForTheSameSeed) {
  Image a = render("seed7_a", "--spp 16 --seed 7");
  Image b = render("seed7_b", "--spp 16 --seed 7");
  ASSERT_EQ(a.rgb.size(), size_t(64) * 48 * 3);
  for (float v : a.rgb) ASSERT_TRUE(std::isfinite(v) && v >= 0.0f) << v;
  EXPECT_EQ(std::memcmp(a.rgb.data(), b.rgb.data(), a.rgb.size() * sizeof(float)), 0)
      << "same seed, other image";
  Image c = render("seed8", "--spp 16 --seed 8");
  EXPECT_NE(std::memcmp(a.rgb.data(), c.rgb.data(), a.rgb.size() * sizeof(float)), 0)
      << "the seed changes nothing";
}

TEST(PathTracer, LightPixelsShowTheLightsRadiance) {
  // One bounce: a light pixel is the emitted radiance plus light reflected from the light itself,
  // which is zero (the light cannot light its own face), so it is exactly 15.
  Image one = render("light_b1", "--spp 4 --bounces 1");
  float brightest = 0;
  size_t light_pixels = 0;
  for (uint32_t y = 0; y < one.height; ++y)
    for (uint32_t x = 0; x < one.width; ++x) {
      brightest = std::max(brightest, one.at(x, y)[0]);
      if (one.at(x, y)[0] > 14.0f) {
        ++light_pixels;
        for (int c = 0; c < 3; ++c) EXPECT_NEAR(one.at(x, y)[c], 15.0f, 1e-4f) << x << "," << y;
      }
    }
  EXPECT_GT(light_pixels, 4u) << "the light is not in view";
  EXPECT_NEAR(brightest, 15.0f, 1e-4f);
  // More bounces only add light reflected by the light's face.
  Image three = render("light_b3", "--spp 16 --bounces 3");
  for (uint32_t y = 0; y < one.height; ++y) {
    for (uint32_t x = 0; x < one.width; ++x) {
      if (one.at(x, y)[0] > 14.0f) {
        EXPECT_GE(three.at(x, y)[0], 15.0f - 1e-4f);
      }
    }
  }
}

TEST(PathTracer, LeftWallIsRedAndRightWallGreen) {
  Image image = render("walls", "--spp 32");
  // The side walls span about 20-32 % and 68-80 % of the width at mid height.
  auto left = mean(image, 0.22, 0.30, 0.40, 0.60), right = mean(image, 0.70, 0.78, 0.40, 0.60);
  EXPECT_GT(left[0], 2.0 * left[1]) << "left wall R " << left[0] << " G " << left[1];
  EXPECT_GT(left[0], 2.0 * left[2]);
  EXPECT_GT(right[1], 2.0 * right[0]) << "right wall G " << right[1] << " R " << right[0];
  EXPECT_GT(right[1], 2.0 * right[2]);
}

// A moving view (--move-frames: the camera turns by itself) is traced at a fraction of the window's size
// chosen for the moving frame target, and the report gives the moving and the still frames apart.
TEST(PathTracer, WindowReportsMovingAndStillFramesApart) {
  auto [status, output] = statepack::testing::run_command(
      "xvfb-run -a -s '-screen 0 800x600x24' '" + std::string(STATEPACK_PATH_TRACER) +
      "' --frames 10 --move-frames 5 --width 640 --height 480");
  ASSERT_EQ(status, 0) << output;
  static const std::regex moving(
      R"(  moving: 5 frames, traced at (\d+)x(\d+) \(1/(\d)\), frame time median \d+ ms)");
  static const std::regex still(
      R"(  still: 4 frames, traced at 640x480, frame time median \d+ ms, .*; \d+ samples per pixel)");
  std::smatch m;
  ASSERT_TRUE(std::regex_search(output, m, moving)) << output;
  const int divisor = std::stoi(m[3]);
  EXPECT_EQ(std::stoi(m[1]), (640 + divisor - 1) / divisor) << output;
  EXPECT_EQ(std::stoi(m[2]), (480 + divisor - 1) / divisor) << output;
  EXPECT_TRUE(std::regex_search(output, still)) << output;
}

// The window path: under a virtual X server the program renders frames into a swapchain (with the
// panel on top) and saves what the window shows; the room must be in it.
TEST(PathTracer, WindowUnderXvfbShowsTheRoom) {
  fs::path shot = fs::path(STATEPACK_TEST_OUTPUT_DIR) / "window.png";
  fs::create_directories(shot.parent_path());
  fs::remove(shot);
  auto [status, output] = statepack::testing::run_command(
      "xvfb-run -a -s '-screen 0 800x600x24' '" + std::string(STATEPACK_PATH_TRACER) +
      "' --frames 12 --width 640 --height 480 --screenshot '" + shot.string() + "'");
  ASSERT_EQ(status, 0) << output;
  EXPECT_NE(output.find("window screenshot"), std::string::npos) << output;
  // --frames reports the frame times the pacer achieved (what docs/path_tracer.md quotes).
  EXPECT_NE(
      output.find(
          "path_tracer: 12 frames at 640x480\n  still: 11 frames, traced at 640x480, frame time median "),
      std::string::npos)
      << output;
  int w = 0, h = 0, channels = 0;
  unsigned char* pixels = stbi_load(shot.c_str(), &w, &h, &channels, 3);
  ASSERT_NE(pixels, nullptr) << stbi_failure_reason();
  ASSERT_EQ(w, 640);
  ASSERT_EQ(h, 480);
  auto region = [&](double x0, double x1, double y0, double y1) {
    std::array<double, 3> sum{};
    size_t n = 0;
    for (int y = int(y0 * h); y < int(y1 * h); ++y)
      for (int x = int(x0 * w); x < int(x1 * w); ++x, ++n)
        for (int c = 0; c < 3; ++c) sum[c] += pixels[(size_t(y) * w + x) * 3 + c];
    for (auto& v : sum) v /= double(n);
    return sum;
  };
  // Below the panel (top left): the red wall's lower part, the green wall, the grey back wall.
  auto left = region(0.22, 0.30, 0.65, 0.80), right = region(0.70, 0.78, 0.40, 0.60);
  auto back = region(0.45, 0.55, 0.60, 0.66);
  stbi_image_free(pixels);
  EXPECT_GT(left[0], 1.5 * left[1]) << "left " << left[0] << "," << left[1] << "," << left[2];
  EXPECT_GT(right[1], 1.5 * right[0]) << "right " << right[0] << "," << right[1] << "," << right[2];
  EXPECT_GT(back[0], 20.0) << "the back wall is dark";
  EXPECT_NEAR(back[0], back[2], 0.2 * back[0] + 4) << "the back wall is not grey";
}

TEST(PathTracer, WritesPngAndExr) {
  for (const char* name : {"out.png", "out.exr"}) {
    fs::path out = fs::path(STATEPACK_TEST_OUTPUT_DIR) / name;
    fs::remove(out);
    std::string output;
    ASSERT_EQ(run("--width 32 --height 24 --spp 2 --out '" + out.string() + "'", output), 0) << output;
    std::ifstream file(out, std::ios::binary);
    unsigned char magic[4] = {};
    file.read(reinterpret_cast<char*>(magic), 4);
    if (out.extension() == ".png") {
      EXPECT_EQ(magic[1], 'P');
      EXPECT_EQ(magic[2], 'N');
    } else {
      EXPECT_EQ(magic[0], 0x76);  // OpenEXR magic 76 2f 31 01
      EXPECT_EQ(magic[3], 0x01);
    }
  }
  std::string output;
  EXPECT_NE(run("--width 32 --height 24 --spp 1 --out x.bmp", output), 0);
  EXPECT_NE(output.find("use .png, .exr or .pfm"), std::string::npos) << output;
}

TEST(PathTracer, BadSceneIsAClearError) {
  fs::path scene = fs::path(STATEPACK_TEST_OUTPUT_DIR) / "bad_scene.json";
  fs::create_directories(scene.parent_path());
  std::ofstream(scene) << R"({ "boxes": [ { "center": [0, 0, 0], "half_size": [1, -1, 1] } ], "light": {} })";
  std::string output;
  EXPECT_NE(run("--scene '" + scene.string() + "' --out x.pfm", output), 0);
  EXPECT_NE(output.find("bad_scene.json"), std::string::npos) << output;
  EXPECT_NE(output.find("/boxes/0/half_size/1"), std::string::npos) << output;
}

TEST(PathTracer, HostileScenesAndOutputsAreErrorsNotCrashesOrBadImages) {
  const fs::path dir = fs::path(STATEPACK_TEST_OUTPUT_DIR) / "hostile";
  fs::remove_all(dir);
  fs::create_directories(dir);
  std::string output;
  // A number beyond a double, and a FIFO (refused without blocking), as the scene.
  std::ofstream(dir / "overflow.json") << R"({"light": {"intensity": 1e999}})";
  EXPECT_EQ(run("--scene '" + (dir / "overflow.json").string() + "' --out '" + (dir / "a.pfm").string() + "'",
                output),
            1);
  EXPECT_NE(output.find("overflow.json: invalid JSON: "), std::string::npos) << output;
  EXPECT_NE(output.find("number overflow parsing '1e999'"), std::string::npos) << output;
  ASSERT_EQ(::mkfifo((dir / "fifo.json").c_str(), 0600), 0);
  EXPECT_EQ(
      run("--scene '" + (dir / "fifo.json").string() + "' --out '" + (dir / "a.pfm").string() + "'", output),
      1);
  EXPECT_NE(output.find("fifo.json: cannot read: it is a FIFO, not a regular file"), std::string::npos)
      << output;
  // Coordinates beyond any room are refused by the scene reader.
  std::ofstream(dir / "far.json") << R"({"camera": {"position": [0, 1, -3e30]}})";
  EXPECT_EQ(
      run("--scene '" + (dir / "far.json").string() + "' --out '" + (dir / "a.pfm").string() + "'", output),
      1);
  EXPECT_NE(output.find("must be a number from -1e6 to 1e6 [/camera/position/2]"), std::string::npos)
      << output;
  // Radiance beyond what any light needs is refused before rendering (sums stay finite in float).
  std::string bright = read_file(STATEPACK_DEFAULT_SCENE_FILE);
  ASSERT_NE(bright.find("\"intensity\": 15"), std::string::npos);
  bright.replace(bright.find("\"intensity\": 15"), 15, "\"intensity\": 3e38");
  std::ofstream(dir / "bright.json") << bright;
  EXPECT_EQ(
      run("--scene '" + (dir / "bright.json").string() + "' --out '" + (dir / "bright.pfm").string() + "'",
          output),
      1);
  EXPECT_NE(output.find("bright.json: must be a number from 0 to 1e6 [/light/intensity]"), std::string::npos)
      << output;
  EXPECT_FALSE(fs::exists(dir / "bright.pfm"));
  // Every other number of the scene and of the command line is range-checked too: a negative light
  // colour, a pitch beyond straight up, a rotation of 1e30 degrees, an exposure of NaN, infinity, zero
  // or below (CLI11's own Range would let NaN through).
  const std::string scene = read_file(STATEPACK_DEFAULT_SCENE_FILE);
  struct Bad {
    const char* file;
    const char* key;
    const char* value;
    const char* message;
  };
  for (const Bad& bad : {Bad{"dark.json", "\"color\": [1", "\"color\": [-1",
                             "dark.json: must be from 0 to 1e6 / intensity (the light's radiance is colour x "
                             "intensity, at most 1e6) [/light/color/0]"},
                         Bad{"pitch.json", "\"pitch_degrees\": 0", "\"pitch_degrees\": 91",
                             "pitch.json: must be a number from -90 to 90 [/camera/pitch_degrees]"},
                         Bad{"spin.json", "\"yaw_degrees\": 0", "\"yaw_degrees\": 1e30",
                             "spin.json: must be a number from -36000 to 36000 [/camera/yaw_degrees]"}}) {
    std::string text = scene;
    ASSERT_NE(text.find(bad.key), std::string::npos) << bad.key;
    text.replace(text.find(bad.key), std::string(bad.key).size(), bad.value);
    std::ofstream(dir / bad.file) << text;
    EXPECT_EQ(
        run("--scene '" + (dir / bad.file).string() + "' --out '" + (dir / "bad.pfm").string() + "'", output),
        1)
        << bad.file;
    EXPECT_NE(output.find(bad.message), std::string::npos) << output;
    EXPECT_FALSE(fs::exists(dir / "bad.pfm")) << bad.file;
  }
  for (const char* exposure : {"nan", "inf", "-inf", "0", "-1", "1e7", "x"}) {
    EXPECT_NE(
        run(std::string("--exposure ") + exposure + " --out '" + (dir / "bad.pfm").string() + "'", output), 0)
        << exposure;
    EXPECT_NE(output.find("--exposure: '" + std::string(exposure) + "' is not a number in (0, 1e6]"),
              std::string::npos)
        << output;
    EXPECT_FALSE(fs::exists(dir / "bad.pfm")) << exposure;
  }
  // The output may not replace the scene it read (however the path reaches it), nor follow a link: a
  // usage error before any rendering.
  fs::copy_file(STATEPACK_DEFAULT_SCENE_FILE, dir / "scene.png");
  const std::string before = read_file(dir / "scene.png");
  fs::create_directories(dir / "sub");
  fs::create_hard_link(dir / "scene.png", dir / "hard.png");
  for (const fs::path& out : {dir / "scene.png", dir / "sub" / ".." / "scene.png", dir / "hard.png"}) {
    EXPECT_EQ(run("--width 16 --height 12 --spp 1 --scene '" + (dir / "scene.png").string() + "' --out '" +
                      out.string() + "'",
                  output),
              2)
        << out;
    EXPECT_NE(output.find("--out: refusing to write"), std::string::npos) << output;
    EXPECT_NE(output.find("it is the input"), std::string::npos) << output;
    EXPECT_EQ(read_file(dir / "scene.png"), before);
  }
  fs::create_symlink(dir / "scene.png", dir / "link.png");
  EXPECT_EQ(run("--width 16 --height 12 --spp 1 --out '" + (dir / "link.png").string() + "'", output), 2);
  EXPECT_NE(output.find("it is a symbolic link"), std::string::npos) << output;
  EXPECT_EQ(read_file(dir / "scene.png"), before);
  // The window's screenshot too, checked before a window opens (so no display is needed to see it).
  auto windowed = statepack::testing::run_command(
      std::string("DISPLAY=:statepack-none '") + STATEPACK_PATH_TRACER + "' --frames 1 --scene '" +
      (dir / "scene.png").string() + "' --screenshot '" + (dir / "hard.png").string() + "'");
  EXPECT_EQ(windowed.exit_code, 2) << windowed.output;
  EXPECT_NE(windowed.output.find("--screenshot: refusing to write"), std::string::npos) << windowed.output;
  EXPECT_EQ(read_file(dir / "scene.png"), before);
}

}  // namespace

// --watch: a new build of the archive, written while the path tracer renders, is reloaded and the
// accumulation starts again with the new pipelines: the image says what the edited shader writes.
TEST(PathTracer, WatchReloadsANewBuildWhileRenderingAndTheImageShowsTheEditedShader) {
  const fs::path dir = fs::path(STATEPACK_TEST_OUTPUT_DIR) / "watch";
  fs::remove_all(dir);
  fs::create_directories(dir);
  fs::copy(fs::path(STATEPACK_SOURCE_DIR) / "shaders", dir / "shaders", fs::copy_options::recursive);
  fs::copy(fs::path(STATEPACK_SOURCE_DIR) / "states", dir, fs::copy_options::recursive);  // and its imports
  auto pack = [&](const std::string& out) {
    auto r = statepack::testing::run_command(
        "'" STATEPACK_EXE "' pack --vulkan -s '" + (dir / "shaders").string() + "' -i '" +
        (dir / "path_tracer.json").string() + "' -o '" + (dir / out).string() + "'");
    EXPECT_EQ(r.exit_code, 0) << r.output;
  };
  pack("pt.spk");
  // The edit: every pixel's mean radiance becomes one colour.
  const fs::path shader = dir / "shaders/path_tracer/path_trace.comp";
  std::string text = read_file(shader);
  const std::string store = "imageStore(accumulation, pixel, vec4(mean, 1.0));";
  const size_t at = text.find(store);
  ASSERT_NE(at, std::string::npos) << "the path-tracing shader no longer stores `mean`: update this test";
  text.replace(at, store.size(), "imageStore(accumulation, pixel, vec4(0.25, 0.5, 0.75, 1.0));");
  std::ofstream(shader, std::ios::binary | std::ios::trunc) << text;
  pack("pt_next.spk");  // built before, renamed over while rendering: as `statepack pack --watch` writes

  const fs::path out = dir / "watched.pfm", log = dir / "log.txt";
  const std::string run = "'" + std::string(STATEPACK_PATH_TRACER) + "' --headless --watch --archive '" +
                          (dir / "pt.spk").string() +
                          "' --width 8 --height 8 --samples-per-frame 1 --spp 3000 --out '" + out.string() +
                          "' >'" + log.string() + "' 2>&1 & pid=$!\n";
  auto r = statepack::testing::run_command(
      run + "for i in $(seq 100); do grep -q watching '" + log.string() +
      "' && break; sleep 0.1; done\nmv '" + (dir / "pt_next.spk").string() + "' '" +
      (dir / "pt.spk").string() + "'\nwait $pid; echo exit=$?; cat '" + log.string() + "'");
  ASSERT_NE(r.output.find("exit=0"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("reload 1 of"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("'Path Trace PSO'"), std::string::npos) << r.output;
  Image image = read_pfm(out);
  ASSERT_EQ(image.width, 8u);
  for (uint32_t y = 0; y < image.height; ++y)
    for (uint32_t x = 0; x < image.width; ++x) {
      EXPECT_FLOAT_EQ(image.at(x, y)[0], 0.25f) << x << "," << y;
      EXPECT_FLOAT_EQ(image.at(x, y)[2], 0.75f) << x << "," << y;
    }
}
