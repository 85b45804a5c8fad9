// Keeps the window responsive: plans how many samples per pixel a frame traces so that the frame's
// path tracing stays near a time target, from the measured GPU time of earlier frames. Pure logic (no
// Vulkan, no window), so it is unit-tested (tests/samples/frame_pacing_test.cpp).
#pragma once

#include <cstdint>

namespace statepack::path_tracer {

struct FramePacing {
  double target_ms = 100;     // path-tracing time a frame may take
  uint32_t max_samples = 32;  // the most samples per pixel one dispatch traces
  double smoothing = 0.3;     // weight of the newest measurement in the running estimate
};

class FramePacer {
 public:
  explicit FramePacer(FramePacing pacing = {}) : pacing_(pacing) {}

  // The last frame's path-tracing dispatch took `gpu_ms` for `samples` samples per pixel. Resets the
  // estimate when the image size changed (`pixels`), since the cost per sample scales with it.
  void measured(double gpu_ms, uint32_t samples, uint64_t pixels);

  // Samples per pixel for the next frame: as many as fit the target, at least 1 and at most
  // max_samples; 1 while the camera or the light moves (the accumulation restarts every frame then, so
  // one sample answers fastest), and 1 until a frame has been measured.
  uint32_t samples_for_next_frame(bool moving) const;

  void set_target_ms(double target_ms) { pacing_.target_ms = target_ms; }

  // The running estimate of one sample's cost in milliseconds (0: nothing measured yet).
  double ms_per_sample() const { return ms_per_sample_; }

 private:
  FramePacing pacing_;
  double ms_per_sample_ = 0;
  uint64_t pixels_ = 0;
};

}  // namespace statepack::path_tracer
