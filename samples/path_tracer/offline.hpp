// Renders N samples per pixel into memory: what the headless mode and the accuracy report share.
#pragma once

#include <functional>
#include <vector>

#include "renderer.hpp"

namespace statepack::path_tracer {

struct OfflineRender {
  std::vector<float> rgba;           // accumulated mean radiance, RGBA32F, rows top to bottom
  double seconds = 0;                // wall time of all batches (submit to finish)
  std::vector<double> batch_gpu_ms;  // GPU time of each batch's path-tracing dispatch
  std::vector<double> batch_wall_ms;
};

// `progress(done, total, seconds)` is called after each batch; `between_batches`, when given, too, and
// returning true starts the accumulation again (a reload changed a pipeline).
Result<OfflineRender> render_offline(bootstrap::VulkanContext& vk, Dearchiver& dearchiver, const Scene& scene,
                                     const RenderSettings& settings, uint32_t width, uint32_t height,
                                     uint32_t spp,
                                     const std::function<void(uint32_t, uint32_t, double)>& progress = {},
                                     const std::function<bool()>& between_batches = {});

}  // namespace statepack::path_tracer
