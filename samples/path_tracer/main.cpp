// path_tracer: the Cornell box of Diligent's Tutorial25, rendered entirely from a statepack archive.
// Headless (default without a display): renders N samples per pixel to PNG, EXR or PFM. Windowed:
// GLFW window with camera and light controls and a settings panel.
#include <unistd.h>
#include <CLI/CLI.hpp>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "app.hpp"

namespace {

using statepack::path_tracer::ChoiceNames;

template <size_t N>
std::vector<std::string> options_of(const ChoiceNames (&names)[N]) {
  std::vector<std::string> out;
  for (const ChoiceNames& n : names) out.push_back(n.option);
  return out;
}

// The enum value whose option is `value` (CLI11 checked it is one of them).
template <class Enum, size_t N>
Enum parse_choice(const std::string& value, const ChoiceNames (&names)[N]) {
  for (size_t i = 0; i < N; ++i)
    if (value == names[i].option) return Enum(i);
  return Enum(0);
}

// A finite number in (low, high], which `range` spells. CLI::Range would let NaN through (every
// comparison with it is false), and "nan" and "inf" parse as floats.
CLI::Validator finite_in(double low, double high, const std::string& range) {
  return CLI::Validator(
      [=](std::string& text) -> std::string {
        char* end = nullptr;
        const double value = std::strtod(text.c_str(), &end);
        if (end == text.c_str() || *end != '\0' || !std::isfinite(value) || !(value > low && value <= high))
          return "'" + text + "' is not a number in " + range;
        return {};
      },
      "NUMBER in " + range);
}

}  // namespace

int main(int argc, char** argv) {
  using namespace statepack::path_tracer;
  Options o;
  CLI::App app{
      "path_tracer: a path-traced Cornell box whose three pipelines come from a statepack archive.\n"
      "Without a display (or with --headless) it renders --spp samples per pixel to --out."};
  app.add_flag("--headless", o.headless,
               "Render to a file instead of a window (the default without a display)");
  app.add_option("--archive", o.archive,
                 "The archive holding 'G-Buffer PSO', 'Path Trace PSO', 'Resolve PSO'")
      ->capture_default_str();
  app.add_option("--scene", o.scene, "Scene file (JSON: boxes and one light)")->capture_default_str();
  app.add_option("--width", o.width, "Image width")->capture_default_str()->check(CLI::Range(8u, 8192u));
  app.add_option("--height", o.height, "Image height")->capture_default_str()->check(CLI::Range(8u, 8192u));
  app.add_option("--spp", o.spp, "Samples per pixel (headless)")
      ->capture_default_str()
      ->check(CLI::Range(1u, 1u << 20));
  app.add_option("--bounces", o.settings.bounces, "Diffuse bounces (1-8)")
      ->capture_default_str()
      ->check(CLI::Range(1u, 8u));
  app.add_option("--samples-per-frame", o.settings.samples_per_frame,
                 "Samples per pixel in one dispatch (1-32)")
      ->capture_default_str()
      ->check(CLI::Range(1u, 32u));
  std::string light_sampling = "solid-angle";
  app.add_option("--light-sampling", light_sampling,
                 "How NEE and MIS sample the light: solid-angle (uniform in the solid angle the rectangle "
                 "subtends) or area (uniform over its area)")
      ->capture_default_str()
      ->check(CLI::IsMember(options_of(kLightSamplingNames)));
  std::string delta_lights = "all";
  app.add_option("--delta-lights", delta_lights,
                 "How NEE treats the scene's lights without area at a vertex: all (a shadow ray each) or one "
                 "(chosen in proportion to its unshadowed contribution)")
      ->capture_default_str()
      ->check(CLI::IsMember(options_of(kDeltaLightsNames)));
  app.add_option("--roulette", o.settings.roulette_start,
                 "Russian roulette from this bounce on (0: never); --bounces stays the maximum")
      ->capture_default_str()
      ->check(CLI::Range(0u, 8u));
  app.add_option("--seed", o.settings.seed, "Random seed: the same seed gives the same image, bit for bit")
      ->capture_default_str();
  app.add_option("--exposure", o.settings.exposure, "Scale applied before tone mapping (PNG and window)")
      ->capture_default_str()
      ->check(finite_in(0, 1e6, "(0, 1e6]"));
  bool no_nee = false;
  std::string estimator = "nee";
  app.add_option("--estimator", estimator,
                 "nee (next-event estimation), bsdf (pure BSDF sampling), mis (both, power heuristic) or "
                 "baseline (the tutorial's estimator)")
      ->capture_default_str()
      ->check(CLI::IsMember(options_of(kEstimatorNames)));
  app.add_flag("--no-nee", no_nee, "Same as --estimator bsdf");
  std::string sampler = "sobol";
  app.add_option("--sampler", sampler,
                 "sobol (Owen-scrambled Sobol points per pixel and dimension pair) or random (independent "
                 "random numbers); the baseline estimator always uses random")
      ->capture_default_str()
      ->check(CLI::IsMember(options_of(kSamplerNames)));
  app.add_flag("--last-bounce-only", o.settings.last_bounce_only, "Show only the light of the last bounce");
  app.add_option("--out", o.out, "Output image: .png (tone-mapped sRGB), .exr or .pfm (linear radiance)")
      ->capture_default_str();
  app.add_option("--frames", o.frames, "Windowed: close after this many frames (0: run until closed)");
  app.add_option("--move-frames", o.move_frames,
                 "Windowed: the camera turns by itself for this many first frames, as a moving view (with "
                 "--frames, the report gives the moving and the still frames apart)");
  app.add_option("--screenshot", o.screenshot,
                 "Windowed: save the last frame's accumulated image here on exit");
  app.add_flag("--watch", o.watch,
               "Reload the archive whenever a new build of it is written (beside `statepack pack --watch`), "
               "restarting the accumulation when a pipeline changed");
  app.add_flag(
      "!--no-validation", o.validation,
      "Run without the Vulkan validation layer (by default it is on, and any message fails the run)");
  // CLI11's messages quote what was typed: escaped like every other name that reaches the terminal.
  app.failure_message([](const CLI::App*, const CLI::Error& e) {
    return printable(e.what()) + "\nRun with --help for more information.\n";
  });
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e) == 0 ? 0 : 2;  // --help is 0; every usage error is 2, as in statepack
  }
  if (no_nee) estimator = "bsdf";
  o.settings.estimator = parse_choice<Estimator>(estimator, kEstimatorNames);
  o.settings.next_event_estimation = o.settings.estimator != Estimator::bsdf;
  o.settings.sampler = parse_choice<Sampler>(sampler, kSamplerNames);
  o.settings.light_sampling = parse_choice<LightSampling>(light_sampling, kLightSamplingNames);
  o.settings.delta_lights = parse_choice<DeltaLights>(delta_lights, kDeltaLightsNames);
  if (!o.headless && !std::getenv("DISPLAY") && !std::getenv("WAYLAND_DISPLAY")) o.headless = true;
  return o.headless ? run_headless(o) : run_windowed(o);
}
