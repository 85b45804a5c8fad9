#include "frame_pacing.hpp"

#include <algorithm>
#include <cmath>

namespace statepack::path_tracer {

void FramePacer::measured(double gpu_ms, uint32_t samples, uint64_t pixels) {
  if (samples == 0 || pixels == 0 || !(gpu_ms > 0) || !std::isfinite(gpu_ms)) return;  // no timestamp yet
  const double per_pixel_sample = gpu_ms / (double(samples) * double(pixels));
  // Smoothed, so one slow frame (another process taking the cores) does not halve the next frame's work.
  if (ms_per_pixel_sample_ == 0)
    ms_per_pixel_sample_ = per_pixel_sample;
  else
    ms_per_pixel_sample_ += pacing_.smoothing * (per_pixel_sample - ms_per_pixel_sample_);
  pixels_ = pixels;
}

uint32_t FramePacer::samples_for_next_frame(bool moving, uint64_t pixels) const {
  const double per_sample = ms_per_sample(pixels);
  if (moving || per_sample <= 0) return 1;
  const double fit = std::floor(pacing_.target_ms / per_sample);
  return uint32_t(std::clamp(fit, 1.0, double(pacing_.max_samples)));
}

uint32_t FramePacer::divisor_for_next_frame(bool moving, uint64_t pixels) const {
  if (!moving || ms_per_pixel_sample_ <= 0) return 1;
  const double budget = pacing_.moving_target_ms * pacing_.moving_trace_share;
  for (uint32_t d = 1; d < pacing_.max_divisor; ++d)
    if (ms_per_sample(pixels) / (double(d) * double(d)) <= budget) return d;
  return pacing_.max_divisor;
}

}  // namespace statepack::path_tracer
