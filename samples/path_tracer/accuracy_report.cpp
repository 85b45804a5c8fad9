// accuracy_report: speed against error for each estimator configuration of the path tracer (estimator,
// sampler, light sampling, Russian roulette), at several bounce counts. For spp = 1, 2, 4, ... it renders
// the default scene on the GPU (from the archive) over several seeds and measures the error against the
// double-precision CPU reference; a separate timing pass, interleaving the configurations round by round
// so that a changing machine load hits them all alike, measures the GPU time per frame at the sweep's
// size and per sample at 640x480. Writes CSVs, log-log plots (with gnuplot when installed) and
// docs/accuracy.md (accuracy_markdown.cpp).
// Run it with: cmake --build build --target report_accuracy
#include <CLI/CLI.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <numeric>
#include <optional>
#include <sstream>

#include "accuracy_markdown.hpp"
#include "app.hpp"
#include "offline.hpp"
#include "reference.hpp"

namespace {

using namespace statepack;
using namespace statepack::path_tracer;
namespace fs = std::filesystem;

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v.empty() ? 0 : v[v.size() / 2];
}

Config make(const char* name, Estimator estimator, Sampler sampler, LightSampling light, uint32_t roulette) {
  Config c{name, {}};
  c.settings.estimator = estimator;
  c.settings.next_event_estimation = estimator != Estimator::bsdf;
  c.settings.sampler = sampler;
  c.settings.light_sampling = light;
  c.settings.roulette_start = roulette;
  return c;
}

// The default with one light without area chosen per vertex instead of all (the same as the default
// in a scene without such lights, where choose_configurations leaves it out).
Config one_delta_light() {
  Config c = make("nee-sobol-solid-rr5-one", Estimator::nee, Sampler::sobol, LightSampling::solid_angle, 5);
  c.settings.delta_lights = DeltaLights::one;
  return c;
}

// The first is today's estimator (before issue 11): every efficiency is compared with it.
std::vector<Config> configurations() {
  using E = Estimator;
  using S = Sampler;
  using L = LightSampling;
  return {make("nee-random-area", E::nee, S::random, L::area, 0),
          make("nee-sobol-area", E::nee, S::sobol, L::area, 0),
          make("nee-random-solid", E::nee, S::random, L::solid_angle, 0),
          make("nee-sobol-solid", E::nee, S::sobol, L::solid_angle, 0),
          make("nee-sobol-solid-rr5", E::nee, S::sobol, L::solid_angle, 5),
          make("nee-sobol-solid-rr4", E::nee, S::sobol, L::solid_angle, 4),
          make("nee-sobol-solid-rr3", E::nee, S::sobol, L::solid_angle, 3),
          make("mis-sobol-solid-rr4", E::mis, S::sobol, L::solid_angle, 4),
          one_delta_light()};
}

// Mean squared error (all pixels and channels) of `rgba` against the reference, its noise subtracted.
std::pair<double, double> errors(const std::vector<float>& rgba, const ReferenceImage& reference,
                                 double reference_noise) {
  const size_t values = size_t(reference.width) * reference.height * 3;
  double mse = 0, rel = 0;
  for (size_t p = 0; p < values / 3; ++p)
    for (int c = 0; c < 3; ++c) {
      const double ref = reference.mean[p * 3 + c], d = rgba[p * 4 + c] - ref;
      mse += d * d, rel += d * d / (ref * ref + 0.01);
    }
  return {mse / double(values) - reference_noise, rel / double(values)};
}

// Median GPU milliseconds per sample of each configuration, over `rounds` rounds that each render
// every configuration once (`spp` samples, `per_frame` per dispatch), and the median wall time.
struct Timing {
  std::vector<double> gpu_ms, wall_ms;
};
Result<Timing> time_interleaved(bootstrap::VulkanContext& vk, Dearchiver& dearchiver, const Scene& scene,
                                const std::vector<Config>& configs, uint32_t bounces, uint32_t width,
                                uint32_t height, uint32_t spp, uint32_t per_frame, uint32_t rounds) {
  std::vector<std::vector<double>> gpu(configs.size()), wall(configs.size());
  for (uint32_t round = 0; round < rounds; ++round)
    for (size_t i = 0; i < configs.size(); ++i) {
      RenderSettings s = configs[i].settings;
      s.bounces = bounces, s.samples_per_frame = per_frame, s.seed = 17 + round;
      auto rendered = render_offline(vk, dearchiver, scene, s, width, height, spp);
      if (!rendered) return rendered.error();
      for (double ms : rendered->batch_gpu_ms) gpu[i].push_back(ms / per_frame);
      for (double ms : rendered->batch_wall_ms) wall[i].push_back(ms / per_frame);
    }
  Timing t;
  for (size_t i = 0; i < configs.size(); ++i)
    t.gpu_ms.push_back(median(gpu[i])), t.wall_ms.push_back(median(wall[i]));
  return t;
}

std::string load_average() {
  double load[3] = {};
  if (getloadavg(load, 3) != 3) return "unknown";
  char text[64];
  std::snprintf(text, sizeof text, "%.2f %.2f %.2f", load[0], load[1], load[2]);
  return text;
}

// The configurations named by --configs, in that order (all when none is named); nullopt when a name is
// unknown.
std::optional<std::vector<Config>> choose_configurations(const std::vector<std::string>& only,
                                                         const Scene& scene) {
  std::vector<Config> all = configurations();
  if (only.empty()) {  // a scene without lights without area would measure the "-one" one twice
    if (light_kinds(scene) == 0)
      std::erase_if(all, [](const Config& c) { return c.settings.delta_lights == DeltaLights::one; });
    return all;
  }
  std::vector<Config> chosen;
  for (const std::string& name : only)
    for (const Config& c : all)
      if (c.name == name) chosen.push_back(c);
  if (chosen.size() != only.size()) return std::nullopt;
  return chosen;
}

// The CPU reference at `bounces`; its time, mean and noise go to the report.
ReferenceImage measure_reference(const Scene& scene, uint32_t bounces, Report& report) {
  BounceResults& r = report.by_bounces[bounces];
  std::printf("CPU reference: %ux%u, %u spp, %u bounces (double precision, all cores)...\n", report.width,
              report.height, report.reference_spp, bounces);
  RenderSettings reference_settings;
  reference_settings.bounces = bounces;
  reference_settings.seed = 0x5EED;
  const auto start = std::chrono::steady_clock::now();
  ReferenceImage reference =
      render_reference(scene, reference_settings, report.width, report.height, report.reference_spp);
  r.reference_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  r.image_mean =
      std::accumulate(reference.mean.begin(), reference.mean.end(), 0.0) / double(reference.mean.size());
  for (double v : reference.variance) r.reference_noise += v / report.reference_spp;
  r.reference_noise /= double(reference.variance.size());
  return reference;
}

// Error against spp: one sample per frame, as the window accumulates. Each run is a row of `runs`.
Result<void> measure_errors(bootstrap::VulkanContext& vk, Dearchiver& dearchiver, const Scene& scene,
                            const ReferenceImage& reference, uint32_t bounces, uint32_t max_spp,
                            std::ostream& runs, Report& report) {
  BounceResults& r = report.by_bounces[bounces];
  const uint32_t width = report.width, height = report.height, seeds = report.seeds;
  for (const Config& config : report.configs) {
    RenderSettings base = config.settings;
    base.bounces = bounces, base.samples_per_frame = 1;
    // Warm up: lavapipe compiles a pipeline's code at its first dispatch.
    if (auto w = render_offline(vk, dearchiver, scene, base, width, height, 2); !w) return w.error();
    std::vector<Point>& points = r.points[config.name];
    for (uint32_t spp = 1; spp <= max_spp; spp *= 2) {
      Point point;
      point.spp = spp;
      for (uint32_t seed = 1; seed <= seeds; ++seed) {
        RenderSettings s = base;
        s.seed = seed * 7919u;
        auto rendered = render_offline(vk, dearchiver, scene, s, width, height, spp);
        if (!rendered) return rendered.error();
        auto [mse, rel] = errors(rendered->rgba, reference, r.reference_noise);
        point.mse += mse / seeds, point.rel_mse += rel / seeds;
        runs << bounces << ',' << config.name << ',' << spp << ',' << seed << ',' << mse << ',' << rel
             << '\n';
      }
      points.push_back(point);
    }
    std::printf("%u bounces, %-20s RMSE at %u spp: %.5f\n", bounces, printable(config.name).c_str(), max_spp,
                points.back().rmse());
  }
  return {};
}

// Time per sample, interleaved: at the sweep's size (one sample per frame) and at 640x480.
Result<void> measure_times(bootstrap::VulkanContext& vk, Dearchiver& dearchiver, const Scene& scene,
                           uint32_t bounces, Report& report) {
  BounceResults& r = report.by_bounces[bounces];
  const uint32_t width = report.width, height = report.height;
  auto small = time_interleaved(vk, dearchiver, scene, report.configs, bounces, width, height, 64, 1,
                                report.timing_rounds);
  if (!small) return small.error();
  auto large =
      time_interleaved(vk, dearchiver, scene, report.configs, bounces, 640, 480, 8, 4, report.timing_rounds);
  if (!large) return large.error();
  for (size_t i = 0; i < report.configs.size(); ++i) {
    const std::string& name = report.configs[i].name;
    r.gpu_ms_per_frame[name] = small->gpu_ms[i];
    r.ms_per_sample_640[name] = large->gpu_ms[i];
    r.wall_ms_per_sample_640[name] = large->wall_ms[i];
    // Time of the sweep's image from the cost per pixel at 640x480: those frames are 100 times
    // larger, so dispatch overhead and load spikes weigh far less than in a 64x48 frame.
    const double ms_per_sample = large->gpu_ms[i] * (double(width) * height) / (640.0 * 480.0);
    for (Point& p : r.points[name]) p.time_s = p.spp * ms_per_sample / 1000.0;
    std::printf("%u bounces, %-20s %.3f ms/frame at %ux%u, %.1f ms/sample at 640x480\n", bounces,
                name.c_str(), small->gpu_ms[i], width, height, large->gpu_ms[i]);
  }
  return {};
}

}  // namespace

int main(int argc, char** argv) {
  std::string archive = STATEPACK_PATH_TRACER_ARCHIVE, scene_path = STATEPACK_DEFAULT_SCENE,
              out_dir = "accuracy";
  std::string doc;
  std::vector<uint32_t> bounce_counts = {3, 8};
  uint32_t width = 64, height = 48, reference_spp = 65536, max_spp = 1024, seeds = 3, timing_rounds = 5;
  CLI::App app{"accuracy_report: error against time and samples for each estimator configuration"};
  app.add_option("--archive", archive)->capture_default_str();
  app.add_option("--scene", scene_path)->capture_default_str();
  app.add_option("--width", width)->capture_default_str()->check(CLI::Range(8u, 8192u));
  app.add_option("--height", height)->capture_default_str()->check(CLI::Range(8u, 8192u));
  app.add_option("--bounces", bounce_counts, "Bounce counts to measure")
      ->capture_default_str()
      ->check(CLI::Range(1u, 8u));
  app.add_option("--reference-spp", reference_spp, "Samples per pixel of the CPU reference")
      ->capture_default_str()
      ->check(CLI::Range(1u, 1u << 24));
  app.add_option("--max-spp", max_spp, "Largest spp of the sweep (powers of two from 1)")
      ->capture_default_str()
      ->check(CLI::Range(1u, 1u << 20));
  app.add_option("--seeds", seeds, "Independent runs per point")
      ->capture_default_str()
      ->check(CLI::Range(1u, 1000u));
  std::vector<std::string> only;
  app.add_option("--configs", only, "Measure only these configurations (the first is the one compared with)");
  app.add_option("--timing-rounds", timing_rounds, "Interleaved rounds of the timing pass")
      ->capture_default_str()
      ->check(CLI::Range(1u, 1000u));
  app.add_option("--out-dir", out_dir, "Where the CSVs, plots and gnuplot script go")->capture_default_str();
  app.add_option("--doc", doc, "Markdown report to write (e.g. docs/accuracy.md)");
  // CLI11's messages quote what was typed: escaped like every other name that reaches the terminal.
  app.failure_message([](const CLI::App*, const CLI::Error& e) {
    return printable(e.what()) + "\nRun with --help for more information.\n";
  });
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e) == 0 ? 0 : 2;  // --help is 0; every usage error is 2
  }

  // Every file this run writes, checked before hours of work: none may replace the archive or the scene
  // (however spelled), be a link or be anything but a regular file.
  const std::vector<fs::path> inputs = {archive, scene_path};
  std::vector<fs::path> outputs = {fs::path(out_dir) / "runs.csv", fs::path(out_dir) / "points.csv",
                                   fs::path(out_dir) / "plot.gnuplot"};
  for (uint32_t bounces : bounce_counts)
    for (const char* plot : {"mse_x_spp_", "error_vs_time_"})
      outputs.push_back(fs::path(out_dir) / (plot + std::to_string(bounces) + ".png"));
  if (!doc.empty()) outputs.emplace_back(doc);
  for (const fs::path& output : outputs)
    if (std::string refused = bootstrap::output_refusal(output, inputs); !refused.empty())
      return std::fprintf(stderr, "accuracy_report: %s\n", printable(refused).c_str()), 2;
  auto scene = load_scene(scene_path);
  if (!scene) return std::fprintf(stderr, "%s\n", printable(scene.error().message).c_str()), 1;
  if (std::error_code ec; !fs::create_directories(out_dir, ec) && ec)
    return std::fprintf(stderr, "accuracy_report: cannot create %s: %s\n", printable(out_dir).c_str(),
                        ec.message().c_str()),
           1;
  Report report;
  auto configs = choose_configurations(only, *scene);
  if (!configs) return std::fprintf(stderr, "accuracy_report: unknown configuration\n"), 2;
  report.configs = std::move(*configs);
  report.width = width, report.height = height, report.seeds = seeds, report.reference_spp = reference_spp;
  report.timing_rounds = timing_rounds;
  report.load_before = load_average();
  report.started = std::chrono::system_clock::now();

  bootstrap::VulkanContextOptions vk_options;
  vk_options.validation = false;  // timing the driver, not the layer
  auto vk = bootstrap::VulkanContext::create(vk_options);
  if (!vk) return std::fprintf(stderr, "%s\n", printable(vk.error().message).c_str()), 1;
  std::ostringstream runs;
  runs << "bounces,config,spp,seed,mse,rel_mse\n";
  {
    auto dearchiver = load_archive(**vk, archive);
    if (!dearchiver) return 1;
    for (uint32_t bounces : bounce_counts) {
      const ReferenceImage reference = measure_reference(*scene, bounces, report);
      if (auto measured =
              measure_errors(**vk, *dearchiver, *scene, reference, bounces, max_spp, runs, report);
          !measured)
        return std::fprintf(stderr, "%s\n", printable(measured.error().message).c_str()), 1;
      if (auto measured = measure_times(**vk, *dearchiver, *scene, bounces, report); !measured)
        return std::fprintf(stderr, "%s\n", printable(measured.error().message).c_str()), 1;
    }
  }
  (*vk)->destroy_device();
  report.load_after = load_average();
  auto write = [&](const fs::path& path, const std::string& text) {
    auto written = bootstrap::write_file_atomically(
        path, {reinterpret_cast<const uint8_t*>(text.data()), text.size()}, inputs);
    if (!written) std::fprintf(stderr, "accuracy_report: %s\n", printable(written.error().message).c_str());
    return bool(written);
  };
  if (!write(fs::path(out_dir) / "runs.csv", runs.str())) return 1;
  const bool plotted = write_plots(report, out_dir, inputs);
  if (!plotted) std::fprintf(stderr, "accuracy_report: gnuplot failed or is missing; no plots drawn\n");
  const std::string md = markdown(report, plotted);
  if (!doc.empty()) {
    if (!write(doc, md)) return 1;
    std::printf("accuracy_report: wrote %s and %s/ (CSVs%s)\n", printable(doc).c_str(),
                printable(out_dir).c_str(), plotted ? ", plots" : "");
  } else {
    std::printf("%s", md.c_str());
  }
  return 0;
}
