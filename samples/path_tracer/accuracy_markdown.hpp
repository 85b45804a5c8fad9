// The accuracy report's results, and how they are written: CSV, gnuplot plots and docs/accuracy.md.
#pragma once

#include <chrono>
#include <cmath>
#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include "renderer.hpp"

namespace statepack::path_tracer {

struct Config {
  std::string name;  // estimator-sampler-light sampling[-rrN]; no spaces (gnuplot splits on them)
  RenderSettings settings;
};

struct Point {
  uint32_t spp = 0;
  double time_s = 0;            // spp * GPU ms per frame
  double mse = 0, rel_mse = 0;  // means over seeds
  double rmse() const { return std::sqrt(std::max(mse, 0.0)); }
  double efficiency() const { return 1.0 / (mse * time_s); }
};

struct BounceResults {
  double reference_seconds = 0, image_mean = 0, reference_noise = 0;
  std::map<std::string, std::vector<Point>> points;  // by configuration name
  std::map<std::string, double> gpu_ms_per_frame, ms_per_sample_640, wall_ms_per_sample_640;
};

struct Report {
  std::vector<Config> configs;  // the first is the one every efficiency is compared with
  uint32_t width = 0, height = 0, seeds = 0, reference_spp = 0, timing_rounds = 0;
  std::string load_before, load_after;
  std::chrono::system_clock::time_point started;
  std::map<uint32_t, BounceResults> by_bounces;
};

// Writes points.csv and plot.gnuplot (atomically, never over one of `inputs`) and runs gnuplot in `dir`;
// false when a file cannot be written (said on stderr) or gnuplot failed or is missing.
bool write_plots(const Report& report, const std::string& dir,
                 const std::vector<std::filesystem::path>& inputs);
std::string markdown(const Report& report, bool plotted);

}  // namespace statepack::path_tracer
