// accuracy_report: speed against error for each estimator. Renders the default scene on the GPU (from
// the archive) for spp = 1, 2, 4, ... over several seeds, times every frame (GPU timestamps and wall
// clock), measures the error against the double-precision CPU reference, and writes a CSV, log-log plots
// (with gnuplot when installed) and docs/accuracy.md.
// Run it with: cmake --build build --target report_accuracy
#include <CLI/CLI.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <map>
#include <numeric>
#include <sstream>

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

struct Point {
  uint32_t spp = 0;
  double gpu_ms_per_frame = 0, wall_ms_per_frame = 0;  // medians over frames and seeds
  double time_s = 0;                                   // spp * GPU ms per frame
  double mse = 0, rel_mse = 0;                         // means over seeds
  double rmse() const { return std::sqrt(std::max(mse, 0.0)); }
  double efficiency() const { return 1.0 / (mse * time_s); }
};

const char* name_of(Estimator e) {
  switch (e) {
    case Estimator::nee:
      return "nee";
    case Estimator::bsdf:
      return "bsdf";
    case Estimator::mis:
      return "mis";
    case Estimator::baseline:
      return "baseline";
  }
  return "?";
}

// Least-squares slope of log y against log x.
double log_log_slope(const std::vector<Point>& points, double (*y)(const Point&)) {
  double sx = 0, sy = 0, sxx = 0, sxy = 0;
  double n = 0;
  for (const auto& p : points) {
    double lx = std::log(double(p.spp)), ly = std::log(y(p));
    sx += lx, sy += ly, sxx += lx * lx, sxy += lx * ly, n += 1;
  }
  return (n * sxy - sx * sy) / (n * sxx - sx * sx);
}

}  // namespace

int main(int argc, char** argv) {
  std::string archive = STATEPACK_PATH_TRACER_ARCHIVE, scene_path = STATEPACK_DEFAULT_SCENE,
              out_dir = "accuracy";
  std::string doc;
  uint32_t width = 64, height = 48, bounces = 3, reference_spp = 65536, max_spp = 1024, seeds = 3;
  CLI::App app{"accuracy_report: error against time and samples for each estimator of the path tracer"};
  app.add_option("--archive", archive)->capture_default_str();
  app.add_option("--scene", scene_path)->capture_default_str();
  app.add_option("--width", width)->capture_default_str();
  app.add_option("--height", height)->capture_default_str();
  app.add_option("--bounces", bounces)->capture_default_str();
  app.add_option("--reference-spp", reference_spp, "Samples per pixel of the CPU reference")
      ->capture_default_str();
  app.add_option("--max-spp", max_spp, "Largest spp of the sweep (powers of two from 1)")
      ->capture_default_str();
  app.add_option("--seeds", seeds, "Independent runs per point")->capture_default_str();
  app.add_option("--out-dir", out_dir, "Where the CSV, plots and gnuplot script go")->capture_default_str();
  app.add_option("--doc", doc, "Markdown report to write (e.g. docs/accuracy.md)");
  CLI11_PARSE(app, argc, argv);

  auto scene = load_scene(scene_path);
  if (!scene) return std::fprintf(stderr, "%s\n", scene.error().message.c_str()), 1;
  fs::create_directories(out_dir);

  RenderSettings base;
  base.bounces = bounces;
  base.samples_per_frame = 1;  // one sample per frame: the frame time is the cost of one sample
  std::printf("CPU reference: %ux%u, %u spp, %u bounces (double precision, all cores)...\n", width, height,
              reference_spp, bounces);
  const auto reference_start = std::chrono::steady_clock::now();
  RenderSettings reference_settings = base;
  reference_settings.seed = 0x5EED;
  ReferenceImage reference = render_reference(*scene, reference_settings, width, height, reference_spp);
  const double reference_seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - reference_start).count();
  const double image_mean =
      std::accumulate(reference.mean.begin(), reference.mean.end(), 0.0) / double(reference.mean.size());
  double reference_noise = 0;  // the reference's own MSE, subtracted from every measured MSE
  for (double v : reference.variance) reference_noise += v / reference_spp;
  reference_noise /= double(reference.variance.size());

  samples::VulkanContextOptions vk_options;
  vk_options.validation = false;  // timing the driver, not the layer
  auto vk = samples::VulkanContext::create(vk_options);
  if (!vk) return std::fprintf(stderr, "%s\n", vk.error().message.c_str()), 1;
  std::map<Estimator, std::vector<Point>> results;
  std::ofstream runs(fs::path(out_dir) / "runs.csv");
  runs << "estimator,spp,seed,gpu_ms_per_frame,wall_ms_per_frame,mse,rel_mse\n";
  {
    auto dearchiver = load_archive(**vk, archive);
    if (!dearchiver) return 1;
    for (Estimator e : {Estimator::nee, Estimator::bsdf, Estimator::mis, Estimator::baseline}) {
      // Warm up: lavapipe compiles a pipeline's code at its first dispatch.
      RenderSettings warm = base;
      warm.estimator = e;
      if (auto w = render_offline(**vk, *dearchiver, *scene, warm, width, height, 2); !w)
        return std::fprintf(stderr, "%s\n", w.error().message.c_str()), 1;
      for (uint32_t spp = 1; spp <= max_spp; spp *= 2) {
        Point point;
        point.spp = spp;
        std::vector<double> gpu_frames, wall_frames;
        for (uint32_t seed = 1; seed <= seeds; ++seed) {
          RenderSettings settings = base;
          settings.estimator = e;
          settings.next_event_estimation = e != Estimator::bsdf;
          settings.seed = seed * 7919u;
          auto rendered = render_offline(**vk, *dearchiver, *scene, settings, width, height, spp);
          if (!rendered) return std::fprintf(stderr, "%s\n", rendered.error().message.c_str()), 1;
          double mse = 0, rel = 0;
          for (size_t p = 0; p < size_t(width) * height; ++p)
            for (int c = 0; c < 3; ++c) {
              const double ref = reference.mean[p * 3 + c], d = rendered->rgba[p * 4 + c] - ref;
              mse += d * d, rel += d * d / (ref * ref + 0.01);
            }
          mse = mse / (double(width) * height * 3) - reference_noise;
          rel /= double(width) * height * 3;
          point.mse += mse / seeds, point.rel_mse += rel / seeds;
          gpu_frames.insert(gpu_frames.end(), rendered->batch_gpu_ms.begin(), rendered->batch_gpu_ms.end());
          wall_frames.insert(wall_frames.end(), rendered->batch_wall_ms.begin(),
                             rendered->batch_wall_ms.end());
          runs << name_of(e) << ',' << spp << ',' << seed << ',' << median(rendered->batch_gpu_ms) << ','
               << median(rendered->batch_wall_ms) << ',' << mse << ',' << rel << '\n';
        }
        point.gpu_ms_per_frame = median(gpu_frames);
        point.wall_ms_per_frame = median(wall_frames);
        point.time_s = spp * point.gpu_ms_per_frame / 1000.0;
        results[e].push_back(point);
        std::printf("%-8s spp %5u: %.3f ms/frame (GPU), RMSE %.5f\n", name_of(e), spp, point.gpu_ms_per_frame,
                    point.rmse());
      }
    }
  }
  (*vk)->destroy_device();

  // Points and plots.
  std::ofstream points(fs::path(out_dir) / "points.csv");
  points << "estimator,spp,gpu_ms_per_frame,wall_ms_per_frame,time_s,rmse,rel_mse,efficiency\n";
  for (const auto& [e, list] : results)
    for (const auto& p : list)
      points << name_of(e) << ',' << p.spp << ',' << p.gpu_ms_per_frame << ',' << p.wall_ms_per_frame << ','
             << p.time_s << ',' << p.rmse() << ',' << p.rel_mse << ',' << p.efficiency() << '\n';
  points.close();
  {
    std::ofstream plot(fs::path(out_dir) / "plot.gnuplot");
    plot << "set datafile separator ','\nset logscale xy\nset grid\nset key top right\n"
            "set terminal pngcairo size 800,560\n"
            "set output 'error_vs_spp.png'\nset xlabel 'samples per pixel'\nset ylabel 'RMSE'\n"
            "set title 'RMSE against samples (default scene, "
         << width << 'x' << height << ", " << bounces
         << " bounces)'\n"
            "plot for [e in 'nee bsdf mis baseline'] 'points.csv' using ((strcol(1) eq e) ? $2 : 1/0):6 "
            "with linespoints title e\n"
            "set output 'error_vs_time.png'\nset xlabel 'GPU time (s, lavapipe)'\n"
            "set title 'RMSE against time'\n"
            "plot for [e in 'nee bsdf mis baseline'] 'points.csv' using ((strcol(1) eq e) ? $5 : 1/0):6 "
            "with linespoints title e\n";
  }
  const std::string gnuplot = "cd '" + out_dir + "' && gnuplot plot.gnuplot";
  const bool plotted = std::system(gnuplot.c_str()) == 0;
  if (!plotted) std::fprintf(stderr, "accuracy_report: gnuplot failed or is missing; no plots drawn\n");

  // The Markdown report.
  std::ostringstream md;
  const double target = 0.01 * image_mean;  // "1 % RMSE": relative to the image's mean radiance
  md << "# Accuracy and speed of the path tracer\n\n"
     << "Made by `cmake --build build --target report_accuracy` (samples/path_tracer/accuracy_report.cpp); "
        "every number below comes from that run.\n\n"
     << "Default scene, " << width << "x" << height << ", " << bounces << " bounces, one sample per frame, "
     << seeds
     << " seeds per point, on lavapipe. Error is measured against a double-precision CPU reference of "
     << "the same integral (" << reference_spp << " spp, " << std::fixed << std::setprecision(1)
     << reference_seconds << " s on all cores), whose own noise (MSE " << std::scientific
     << std::setprecision(2) << reference_noise
     << ") is subtracted. Time is spp times the median GPU time of a frame "
     << "(timestamps around the path-tracing dispatch); the wall time per frame, submission included, is "
        "also "
        "listed. RMSE is over all pixels and channels; relMSE divides each squared error by (reference^2 + "
        "0.01); efficiency is 1/(MSE * time). \"Time to 1 % RMSE\" extrapolates the largest-spp point with "
        "MSE proportional to 1/time to an RMSE of 1 % of the image's mean radiance ("
     << std::fixed << std::setprecision(4) << image_mean << ").\n\n";
  if (plotted)
    md << "![RMSE against time](accuracy/error_vs_time.png)\n![RMSE against "
          "spp](accuracy/error_vs_spp.png)\n\n";
  const auto& baseline = results[Estimator::baseline];
  for (const auto& [e, list] : results) {
    md << "## " << name_of(e) << "\n\n"
       << "| spp | GPU ms/frame | wall ms/frame | RMSE | relMSE | efficiency | time to 1 % RMSE (s) |\n"
       << "|---|---|---|---|---|---|---|\n";
    for (const auto& p : list) {
      const double t1 = p.time_s * p.mse / (target * target);
      md << "| " << p.spp << " | " << std::setprecision(3) << p.gpu_ms_per_frame << " | "
         << p.wall_ms_per_frame << " | " << std::setprecision(5) << p.rmse() << " | " << std::scientific
         << std::setprecision(2) << p.rel_mse << " | " << p.efficiency() << " | " << std::fixed
         << std::setprecision(2) << t1 << " |\n";
    }
    const double slope = log_log_slope(list, [](const Point& p) { return p.rmse(); });
    md << "\nRMSE slope on log-log axes: " << std::setprecision(3) << slope;
    if (e != Estimator::baseline && !list.empty() && !baseline.empty())
      md << "; at the largest spp, efficiency " << std::setprecision(2)
         << list.back().efficiency() / baseline.back().efficiency()
         << "x the baseline's (the MSE ratio at equal time)";
    md << ".\n\n";
  }
  md << "The baseline is the tutorial's estimator (one random pair for the light sample and the bounce, a "
        "global epsilon of 0.05 with the far-hit fallback, no source-box exclusion); its error includes its "
        "bias, so it stops falling at high spp.\n";
  if (!doc.empty()) {
    std::ofstream(doc) << md.str();
    std::printf("accuracy_report: wrote %s, %s/points.csv, %s/runs.csv%s\n", doc.c_str(), out_dir.c_str(),
                out_dir.c_str(), plotted ? " and the plots" : "");
  } else {
    std::printf("%s", md.str().c_str());
  }
  return 0;
}
