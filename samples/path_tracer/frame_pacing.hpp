// Keeps the window responsive: plans how many samples per pixel a frame traces so that the frame's
// path tracing stays near a time target, and, while the view moves, at what fraction of the window's
// size to trace so that a moving frame meets a tighter target, from the measured GPU time of earlier
// frames. Pure logic (no Vulkan, no window), so it is unit-tested (tests/samples/frame_pacing_test.cpp).
#pragma once

#include <cstdint>

namespace statepack::path_tracer {

struct FramePacing {
  double target_ms = 100;     // path-tracing time a frame may take
  uint32_t max_samples = 32;  // the most samples per pixel one dispatch traces
  double smoothing = 0.3;     // weight of the newest measurement in the running estimate
  // While the view moves: the whole frame's target, and the share of it path tracing may take (the
  // G-buffer, the resolve, the panel and presenting take the rest).
  double moving_target_ms = 50;
  double moving_trace_share = 0.5;
  uint32_t max_divisor = 8;  // at the most, 1/8 of the width and height
};

class FramePacer {
 public:
  explicit FramePacer(FramePacing pacing = {}) : pacing_(pacing) {}

  // The last frame's path-tracing dispatch took `gpu_ms` for `samples` samples per pixel over `pixels`
  // traced pixels. The estimate is kept per pixel and sample, so frames traced at a fraction of the size
  // (while moving) and at the full size inform each other.
  void measured(double gpu_ms, uint32_t samples, uint64_t pixels);

  // Samples per pixel for the next frame, which traces `pixels`: as many as fit the target, at least 1
  // and at most max_samples; 1 while the camera or the light moves (the accumulation restarts every
  // frame then, so one sample answers fastest), and 1 until a frame has been measured.
  uint32_t samples_for_next_frame(bool moving, uint64_t pixels) const;

  // The divisor of the width and height to trace at while moving: the smallest (at least 1, at most
  // max_divisor) whose one sample per pixel over `pixels`/divisor² fits the moving target's share;
  // 1 while still, or until a frame has been measured.
  uint32_t divisor_for_next_frame(bool moving, uint64_t pixels) const;

  void set_target_ms(double target_ms) { pacing_.target_ms = target_ms; }
  void set_moving_target_ms(double target_ms) { pacing_.moving_target_ms = target_ms; }

  // The running estimate of one sample's cost in milliseconds over `pixels` pixels (0: nothing measured).
  double ms_per_sample(uint64_t pixels) const { return ms_per_pixel_sample_ * double(pixels); }
  // ... over the pixels of the last measurement.
  double ms_per_sample() const { return ms_per_sample(pixels_); }

 private:
  FramePacing pacing_;
  double ms_per_pixel_sample_ = 0;
  uint64_t pixels_ = 0;
};

}  // namespace statepack::path_tracer
