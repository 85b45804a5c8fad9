#include "accuracy_markdown.hpp"

#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <filesystem>
#include <iomanip>
#include <span>
#include <sstream>
#include <thread>

#include "statepack/bootstrap/host_tools.hpp"

namespace statepack::path_tracer {
namespace {

// Least-squares slope of log RMSE against log spp.
double rmse_slope(const std::vector<Point>& points) {
  double sx = 0, sy = 0, sxx = 0, sxy = 0, n = 0;
  for (const auto& p : points) {
    const double lx = std::log(double(p.spp)), ly = std::log(p.rmse());
    sx += lx, sy += ly, sxx += lx * lx, sxy += lx * ly, n += 1;
  }
  return (n * sxy - sx * sy) / (n * sxx - sx * sx);
}

const Point* at_spp(const std::vector<Point>& points, uint32_t spp) {
  for (const auto& p : points)
    if (p.spp == spp) return &p;
  return nullptr;
}

// Efficiency of `name` relative to the first configuration's at the same spp (0 if not measured).
double efficiency_ratio(const Report& report, const BounceResults& r, const std::string& name, uint32_t spp) {
  const Point* p = at_spp(r.points.at(name), spp);
  const Point* today = at_spp(r.points.at(report.configs.front().name), spp);
  return p && today ? p->efficiency() / today->efficiency() : 0.0;
}

std::string describe(const RenderSettings& s) {
  std::string out = names_of(s.estimator).title;
  out = out + ", " + names_of(s.sampler).title + ", " + names_of(s.light_sampling).title;
  out += s.roulette_start ? ", roulette from bounce " + std::to_string(s.roulette_start) : ", no roulette";
  if (s.delta_lights == DeltaLights::one) out += ", " + std::string(names_of(s.delta_lights).title);
  return out;
}

}  // namespace

bool write_plots(const Report& report, const std::string& dir,
                 const std::vector<std::filesystem::path>& inputs) {
  namespace fs = std::filesystem;
  std::ostringstream points;
  points << "bounces,config,spp,time_s,rmse,mse_x_spp,rel_mse,efficiency\n";
  for (const auto& [bounces, r] : report.by_bounces)
    for (const auto& [name, list] : r.points)
      for (const auto& p : list)
        points << bounces << ',' << name << ',' << p.spp << ',' << p.time_s << ',' << p.rmse() << ','
               << p.mse * p.spp << ',' << p.rel_mse << ',' << p.efficiency() << '\n';
  std::string names;
  for (const auto& c : report.configs) names += (names.empty() ? "" : " ") + c.name;
  std::ostringstream plot;
  plot << "set datafile separator ','\nset logscale xy\nset grid\nset key outside right\n"
          "set terminal pngcairo size 900,520\nconfigs = '"
       << names << "'\n";
  for (const auto& [bounces, r] : report.by_bounces) {
    const std::string b = std::to_string(bounces);
    plot << "set output 'mse_x_spp_" << b << ".png'\nset xlabel 'samples per pixel'\nset ylabel 'MSE x spp'\n"
         << "set title 'MSE x spp against spp (" << report.width << 'x' << report.height << ", " << b
         << " bounces; flat: independent samples)'\n"
         << "plot for [e in configs] 'points.csv' using ((strcol(2) eq e && $1 == " << b
         << ") ? $3 : 1/0):6 with linespoints title e\n"
         << "set output 'error_vs_time_" << b << ".png'\nset xlabel 'GPU time (s, lavapipe)'\n"
         << "set ylabel 'RMSE'\nset title 'RMSE against time (" << b << " bounces)'\n"
         << "plot for [e in configs] 'points.csv' using ((strcol(2) eq e && $1 == " << b
         << ") ? $4 : 1/0):5 with linespoints title e\n";
  }
  for (const auto& [name, text] : {std::pair{"points.csv", points.str()}, {"plot.gnuplot", plot.str()}}) {
    const auto bytes = std::as_bytes(std::span(text));
    auto written = bootstrap::write_file_atomically(
        fs::path(dir) / name, {reinterpret_cast<const uint8_t*>(bytes.data()), bytes.size()}, inputs);
    if (!written) {
      std::fprintf(stderr, "accuracy_report: %s\n", bootstrap::printable(written.error().message).c_str());
      return false;
    }
  }
  // The folder reaches the shell quoted: a quote in it is closed, escaped and reopened.
  std::string quoted = "'";
  for (char c : dir) quoted += c == '\'' ? std::string("'\\''") : std::string(1, c);
  const std::string command = "cd " + quoted + "' && gnuplot plot.gnuplot";
  return std::system(command.c_str()) == 0;
}

std::string markdown(const Report& report, bool plotted) {
  std::ostringstream md;
  const std::time_t started = std::chrono::system_clock::to_time_t(report.started);
  char when[32];
  std::strftime(when, sizeof when, "%Y-%m-%d %H:%M UTC", std::gmtime(&started));
  const std::string& today = report.configs.front().name;
  md << "# Accuracy and speed of the path tracer\n\n"
     << "Made by `cmake --build build --target report_accuracy` (samples/path_tracer/accuracy_report.cpp); "
        "every number below comes from that run, started "
     << when << " on " << std::thread::hardware_concurrency() << " cores with load averages (1, 5, 15 min) "
     << report.load_before << " before and " << report.load_after << " after.\n\n"
     << "**Time numbers are noisy**: this machine's cores are shared with other builds, so a frame's time "
        "depends on their load. The timing pass therefore interleaves the configurations ("
     << report.timing_rounds
     << " rounds, each rendering every configuration once), so that the load hits them alike and their "
        "ratios hold better than their absolute values.\n\n"
     << "Default scene, " << report.width << "x" << report.height << ", one sample per frame, "
     << report.seeds
     << " seeds per point, on lavapipe. Error is measured against a double-precision CPU reference of the "
        "same integral ("
     << report.reference_spp
     << " spp), whose own noise is subtracted. Time is spp times the GPU time of one sample of the image, "
        "taken from the median cost per pixel of a sample at 640x480 in the timing pass (timestamps "
        "around the path-tracing dispatch; those frames are 100 times larger than the sweep's, so "
        "dispatch overhead and load spikes weigh far less; the sweep-size frame time is listed too). RMSE is "
        "over all pixels and "
        "channels; efficiency is 1/(MSE * time); with independent samples MSE * spp is flat, so efficiency "
        "does not depend on spp, while with stratified samples MSE * spp falls and efficiency grows with "
        "spp. \"Efficiency vs "
     << today
     << "\" divides by the efficiency of today's estimator (before issue 11: NEE, independent random "
        "numbers, area light sampling, no roulette) at the same spp; as its efficiency is flat, that is "
        "the MSE ratio at equal time. The per-sample cost at the default window size, 640x480, is measured "
        "with 4 samples per dispatch.\n\n"
     << "Configurations are named estimator-sampler-light sampling, with `-rrN` for Russian roulette from "
        "bounce N.\n\n";
  std::map<std::string, double> log_ratio_sum;
  for (const auto& [bounces, r] : report.by_bounces) {
    md << "## " << bounces << " bounces\n\n"
       << "CPU reference: " << std::fixed << std::setprecision(1) << r.reference_seconds
       << " s on all cores, noise MSE " << std::scientific << std::setprecision(2) << r.reference_noise
       << "; image mean radiance " << std::fixed << std::setprecision(4) << r.image_mean << ".\n\n";
    if (plotted)
      md << "![MSE x spp against spp](accuracy/mse_x_spp_" << bounces
         << ".png)\n![RMSE against time](accuracy/"
         << "error_vs_time_" << bounces << ".png)\n\n";
    md << "| configuration | GPU ms/frame " << report.width << "x" << report.height
       << " | ms/sample 640x480 (GPU) | ms/sample 640x480 (wall) | RMSE at 1024 spp | RMSE slope | "
          "efficiency vs "
       << today << " at 256 spp | at 1024 spp |\n|---|---|---|---|---|---|---|---|\n";
    for (const auto& c : report.configs) {
      const auto& list = r.points.at(c.name);
      const Point* p1024 = at_spp(list, 1024);
      const double at256 = efficiency_ratio(report, r, c.name, 256),
                   at1024 = efficiency_ratio(report, r, c.name, 1024);
      md << "| " << c.name << " | " << std::fixed << std::setprecision(3) << r.gpu_ms_per_frame.at(c.name)
         << " | " << std::setprecision(1) << r.ms_per_sample_640.at(c.name) << " | "
         << r.wall_ms_per_sample_640.at(c.name) << " | " << std::setprecision(5)
         << (p1024 ? p1024->rmse() : 0.0) << " | " << std::setprecision(3) << rmse_slope(list) << " | "
         << std::setprecision(2) << at256 << "x | " << at1024 << "x |\n";
      if (at1024 > 0) log_ratio_sum[c.name] += std::log(at1024);
    }
    md << "\nMSE x spp (lower is better; flat means independent samples):\n\n| spp |";
    for (const auto& c : report.configs) md << ' ' << c.name << " |";
    md << "\n|---|";
    for (size_t i = 0; i < report.configs.size(); ++i) md << "---|";
    md << '\n';
    const auto& first = r.points.at(today);
    for (size_t i = 0; i < first.size(); ++i) {
      md << "| " << first[i].spp << " |";
      for (const auto& c : report.configs)
        md << ' ' << std::scientific << std::setprecision(3) << r.points.at(c.name)[i].mse * first[i].spp
           << " |";
      md << '\n';
    }
    md << '\n';
  }
  // The most efficient configuration at 1024 spp over all bounce counts (geometric mean of the ratios).
  std::string best;
  for (const auto& [name, sum] : log_ratio_sum)
    if (best.empty() || sum > log_ratio_sum[best]) best = name;
  const RenderSettings defaults;
  std::string chosen = "none of the above";
  for (const auto& c : report.configs) {
    RenderSettings s = c.settings;
    s.bounces = defaults.bounces, s.samples_per_frame = defaults.samples_per_frame;
    if (s == defaults) chosen = c.name;
  }
  md << "## Choice of the default\n\nMost efficient at 1024 spp (geometric mean of the efficiency ratios "
        "over "
        "the bounce counts): **"
     << best << "**. The program's default (`RenderSettings`) is **" << chosen << "** (" << describe(defaults)
     << "); docs/path_tracer.md explains the choice.\n\nIssue 11's goals for the default against " << today
     << " at 1024 spp:\n\n";
  for (const auto& [bounces, r] : report.by_bounces) {
    if (!r.points.count(chosen)) continue;
    const double ratio = efficiency_ratio(report, r, chosen, 1024);
    const double ms = r.ms_per_sample_640.at(chosen), ms_today = r.ms_per_sample_640.at(today);
    md << "- " << bounces << " bounces: efficiency " << std::fixed << std::setprecision(2) << ratio << "x ("
       << (ratio >= 2 ? "meets" : "misses") << " the goal of 2x); " << std::setprecision(1) << ms
       << " ms per sample at 640x480 against " << ms_today << " ("
       << (ms < ms_today ? "faster" : "not faster") << ").\n";
  }
  md << "\nThe estimator variants and their unbiasedness tests: [path_tracer.md](path_tracer.md).\n";
  return md.str();
}

}  // namespace statepack::path_tracer
