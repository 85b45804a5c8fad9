// A CPU reference of the GPU path tracer's integral in double precision: the same scene model, the same
// definition of bounces and estimators, the same random numbers, on all cores. It yields a mean image
// and the per-pixel variance of one sample, for per-pixel z-tests and error measurements.
#pragma once

#include <cstdint>
#include <vector>

#include "renderer.hpp"
#include "scene.hpp"

namespace statepack::path_tracer {

struct ReferenceImage {
  uint32_t width = 0, height = 0;
  uint32_t samples = 0;
  std::vector<double> mean;      // RGB per pixel, rows top to bottom
  std::vector<double> variance;  // RGB per pixel: variance of a single sample's value
};

// `settings.seed`, `bounces`, `next_event_estimation` and `last_bounce_only` mean what they mean on
// the GPU; `threads` 0 uses every core.
ReferenceImage render_reference(const Scene& scene, const RenderSettings& settings, uint32_t width,
                                uint32_t height, uint32_t spp, uint32_t threads = 0);

}  // namespace statepack::path_tracer
