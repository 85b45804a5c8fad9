#include "frame_pacing.hpp"

#include <algorithm>
#include <cmath>

namespace statepack::path_tracer {

void FramePacer::measured(double gpu_ms, uint32_t samples, uint64_t pixels) {
  if (samples == 0 || !(gpu_ms > 0) || !std::isfinite(gpu_ms)) return;  // no timestamp (first frame)
  const double per_sample = gpu_ms / samples;
  // A new image size changes the cost outright: start over instead of averaging across it. Otherwise
  // smooth, so one slow frame (another process taking the cores) does not halve the next frame's work.
  if (pixels != pixels_ || ms_per_sample_ == 0)
    ms_per_sample_ = per_sample;
  else
    ms_per_sample_ += pacing_.smoothing * (per_sample - ms_per_sample_);
  pixels_ = pixels;
}

uint32_t FramePacer::samples_for_next_frame(bool moving) const {
  if (moving || ms_per_sample_ <= 0) return 1;
  const double fit = std::floor(pacing_.target_ms / ms_per_sample_);
  return uint32_t(std::clamp(fit, 1.0, double(pacing_.max_samples)));
}

}  // namespace statepack::path_tracer
