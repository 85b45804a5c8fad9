// The window's frame pacing (samples/path_tracer/frame_pacing.hpp): samples per frame follow the
// measured cost toward the frame-time target, stay within 1..max, drop to 1 while the view moves, the
// cost is kept per pixel across image sizes, and moving frames trace at a fraction of the size.
#include <gtest/gtest.h>

#include "path_tracer/frame_pacing.hpp"

namespace {

using statepack::path_tracer::FramePacer;
using statepack::path_tracer::FramePacing;

constexpr uint64_t kPixels = 640 * 480;

TEST(FramePacing, OneSampleUntilMeasuredAndWhileMoving) {
  FramePacer pacer({100, 32, 0.3});
  EXPECT_EQ(pacer.samples_for_next_frame(false, kPixels), 1u);
  pacer.measured(0, 1, kPixels);  // the first frame has no timestamp yet
  EXPECT_EQ(pacer.samples_for_next_frame(false, kPixels), 1u);
  pacer.measured(10, 1, kPixels);
  EXPECT_EQ(pacer.samples_for_next_frame(false, kPixels), 10u);
  EXPECT_EQ(pacer.samples_for_next_frame(true, kPixels), 1u);
}

TEST(FramePacing, FitsTheTargetWithinLimits) {
  FramePacer pacer({100, 32, 0.3});
  pacer.measured(40, 8, kPixels);  // 5 ms per sample: 20 fit in 100 ms
  EXPECT_EQ(pacer.samples_for_next_frame(false, kPixels), 20u);
  FramePacer slow({100, 32, 0.3});
  slow.measured(450, 1, kPixels);  // one sample already exceeds the target: still 1
  EXPECT_EQ(slow.samples_for_next_frame(false, kPixels), 1u);
  FramePacer fast({100, 32, 0.3});
  fast.measured(1, 4, kPixels);  // 0.25 ms per sample: 400 would fit, 32 is the most
  EXPECT_EQ(fast.samples_for_next_frame(false, kPixels), 32u);
}

TEST(FramePacing, SmoothsLoadSpikesAndFollowsLastingChanges) {
  FramePacer pacer({100, 32, 0.3});
  pacer.measured(50, 10, kPixels);   // 5 ms per sample
  pacer.measured(200, 10, kPixels);  // one frame at 20 ms per sample (a spike)
  EXPECT_NEAR(pacer.ms_per_sample(), 5 + 0.3 * 15, 1e-12);
  EXPECT_EQ(pacer.samples_for_next_frame(false, kPixels), 10u);   // 100 / 9.5, not 100 / 20
  for (int i = 0; i < 30; ++i) pacer.measured(100, 10, kPixels);  // a lasting 10 ms per sample
  EXPECT_NEAR(pacer.ms_per_sample(), 10, 1e-3);
  EXPECT_EQ(pacer.samples_for_next_frame(false, kPixels), 10u);
}

// The cost is kept per pixel and sample: frames traced at a quarter of the pixels (while moving) and
// full-size frames inform one estimate.
TEST(FramePacing, KeepsTheCostPerPixelAcrossImageSizes) {
  FramePacer pacer({100, 32, 0.3});
  pacer.measured(40, 8, kPixels);            // 5 ms per sample at 640x480
  pacer.measured(1.25 * 4, 4, kPixels / 4);  // 1.25 ms per sample at 320x240: the same per pixel
  EXPECT_DOUBLE_EQ(pacer.ms_per_sample(kPixels), 5);
  EXPECT_DOUBLE_EQ(pacer.ms_per_sample(kPixels / 4), 1.25);
  pacer.measured(20, 1, 1280 * 960);  // four times the pixels at 20 ms per sample: still 5 at 640x480
  EXPECT_DOUBLE_EQ(pacer.ms_per_sample(kPixels), 5);
  EXPECT_EQ(pacer.samples_for_next_frame(false, kPixels), 20u);    // the next frame at 640x480
  EXPECT_EQ(pacer.samples_for_next_frame(false, 1280 * 960), 5u);  // ... at 1280x960
  // Right after moving frames traced at a quarter of the pixels, a full-size still frame is planned
  // at the full size's cost, not at the small frames' (which would ask for four times too many).
  pacer.measured(1.25, 1, kPixels / 4);
  EXPECT_EQ(pacer.samples_for_next_frame(false, kPixels), 20u);
}

// While moving, the window traces at 1/divisor of its width and height: the smallest divisor whose one
// sample per pixel fits the moving target's share (25 ms of 50 by default); 1 while still.
TEST(FramePacing, MovingFramesTraceAtTheFractionThatFitsTheirTarget) {
  FramePacer pacer;  // moving target 50 ms, half of it for path tracing
  EXPECT_EQ(pacer.divisor_for_next_frame(true, kPixels), 1u);  // nothing measured yet
  pacer.measured(90, 1, kPixels);                              // 90 ms per sample at 640x480
  EXPECT_EQ(pacer.divisor_for_next_frame(false, kPixels), 1u);
  EXPECT_EQ(pacer.divisor_for_next_frame(true, kPixels), 2u);  // 90 / 4 = 22.5 ms <= 25
  pacer.set_moving_target_ms(20);                              // 10 ms: 90 / 9 = 10
  EXPECT_EQ(pacer.divisor_for_next_frame(true, kPixels), 3u);
  FramePacer cheap;
  cheap.measured(10, 1, kPixels);
  EXPECT_EQ(cheap.divisor_for_next_frame(true, kPixels), 1u);  // already fits
  FramePacer hopeless;
  hopeless.measured(100000, 1, kPixels);
  EXPECT_EQ(hopeless.divisor_for_next_frame(true, kPixels), 8u);  // at most 1/8
}

}  // namespace
