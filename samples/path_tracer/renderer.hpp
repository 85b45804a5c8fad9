// The path tracer's GPU side: G-buffer, compute path tracing with next-event estimation, resolve.
// All three pipelines come from the archive; resources are bound by the names the shaders give them.
// One frame in flight: the caller waits for a frame before recording the next.
#pragma once

#include <memory>
#include <vector>

#include "sampler.hpp"
#include "scene.hpp"
#include "statepack/bootstrap/vulkan_context.hpp"
#include "statepack/dearchiver.hpp"

namespace statepack::path_tracer {

// How light paths are estimated; each but `bsdf` is its own pipeline in the archive (Macros variants).
enum class Estimator { nee, bsdf, mis, baseline };
// How next-event estimation picks a point of the rectangular light: uniformly by area, or uniformly in
// the solid angle it subtends (spherical rectangles, Urena et al. 2013).
enum class LightSampling { area, solid_angle };
// How next-event estimation treats the lights without area at a path vertex: every one (a shadow ray
// each), or one chosen in proportion to its unshadowed contribution and divided by that probability.
enum class DeltaLights { all, one };

// The one spelling of each choice: its command-line value and its name in messages, reports and the
// window. Indexed by the enum's value.
struct ChoiceNames {
  const char* option;
  const char* title;
};
inline constexpr ChoiceNames kEstimatorNames[] = {
    {"nee", "NEE"}, {"bsdf", "BSDF sampling"}, {"mis", "MIS"}, {"baseline", "tutorial baseline"}};
inline constexpr ChoiceNames kSamplerNames[] = {{"sobol", "Sobol"}, {"random", "random"}};
inline constexpr ChoiceNames kLightSamplingNames[] = {{"area", "area"}, {"solid-angle", "solid-angle"}};
inline constexpr ChoiceNames kDeltaLightsNames[] = {{"all", "every delta light"}, {"one", "one delta light"}};
inline const ChoiceNames& names_of(Estimator e) {
  return kEstimatorNames[size_t(e)];
}
inline const ChoiceNames& names_of(Sampler s) {
  return kSamplerNames[size_t(s)];
}
inline const ChoiceNames& names_of(LightSampling l) {
  return kLightSamplingNames[size_t(l)];
}
inline const ChoiceNames& names_of(DeltaLights d) {
  return kDeltaLightsNames[size_t(d)];
}

struct RenderSettings {
  uint32_t bounces = 3;               // 1..8
  uint32_t samples_per_frame = 8;     // 1..32
  bool next_event_estimation = true;  // with Estimator::nee: false means pure BSDF sampling
  Estimator estimator = Estimator::nee;
  Sampler sampler = Sampler::sobol;  // ignored by the tutorial baseline, which keeps its random pair
  uint32_t roulette_start = 5;       // Russian roulette from this bounce on (0: never); not in baseline
  LightSampling light_sampling = LightSampling::solid_angle;  // not in baseline
  DeltaLights delta_lights = DeltaLights::all;
  bool last_bounce_only = false;
  uint32_t seed = 1;
  float exposure = 1.0f;
  bool operator==(const RenderSettings&) const = default;
};

class Renderer {
 public:
  // `target_format` is the resolve pipeline's render-target format, patched into it at unpack time.
  static Result<std::unique_ptr<Renderer>> create(bootstrap::VulkanContext& vk, Dearchiver& dearchiver,
                                                  uint32_t width, uint32_t height, VkFormat target_format);
  ~Renderer();

  // Each of these restarts the accumulation when something changed. A scene also picks the path-tracing
  // pipelines specialised for its lights (the unpack can fail: then the previous scene stays).
  Result<void> set_scene(const Scene& scene);
  void set_camera(const Camera& camera);
  void set_settings(const RenderSettings& settings);
  Result<void> resize(uint32_t width, uint32_t height);
  // Traces at 1/divisor of the width and height (1: full size; at most 8), each traced pixel shown as a
  // divisor x divisor block: the window does this while the view moves, where a frame's cost matters more
  // than its detail. A change restarts the accumulation.
  void set_render_divisor(uint32_t divisor);
  uint32_t render_divisor() const { return divisor_; }
  uint32_t render_width() const { return (width_ + divisor_ - 1) / divisor_; }
  uint32_t render_height() const { return (height_ + divisor_ - 1) / divisor_; }

  // Records one frame: the G-buffer when the view changed, one batch of samples, and the resolve into
  // `target` (a color-attachment image of the target format), left in `final_layout`.
  void record(VkCommandBuffer cmd, VkImage target, VkImageView target_view, VkImageLayout final_layout);

  uint32_t samples_done() const { return samples_done_; }
  // Starts the accumulation again, e.g. after a reload changed a pipeline (its pointers read the new one).
  void restart_accumulation() { restart(); }
  // GPU time of the last recorded batch's path-tracing dispatch, in milliseconds (after it finished).
  double last_trace_ms() const;
  uint32_t width() const { return width_; }
  uint32_t height() const { return height_; }
  const Scene& scene() const { return scene_; }
  const Camera& camera() const { return scene_.camera; }
  const RenderSettings& settings() const { return settings_; }

  // The accumulated mean radiance, RGBA32F, rows top to bottom (waits for the device).
  Result<std::vector<float>> read_accumulation();

 private:
  using Image = std::unique_ptr<bootstrap::DeviceImage>;
  Renderer(bootstrap::VulkanContext& vk) : vk_(vk) {}
  Result<void> create_images();
  void destroy_images();
  void write_descriptors();
  void upload_scene();
  Result<void> specialize(const Scene& scene);
  void write_constants();
  void restart() { samples_done_ = 0, gbuffer_dirty_ = true; }

  bootstrap::VulkanContext& vk_;
  Dearchiver* dearchiver_ = nullptr;
  const UnpackedPipeline* gbuffer_ = nullptr;
  const UnpackedPipeline* trace_ = nullptr;  // next-event estimation (and BSDF sampling)
  const UnpackedPipeline* trace_mis_ = nullptr;
  const UnpackedPipeline* trace_baseline_ = nullptr;
  const UnpackedPipeline* resolve_ = nullptr;
  VkFormat target_format_ = VK_FORMAT_UNDEFINED;
  uint32_t width_ = 0, height_ = 0;
  uint32_t divisor_ = 1;
  Scene scene_;
  uint32_t light_index_ = 0, box_count_ = 0, light_count_ = 0;
  bool other_emitters_ = false;
  RenderSettings settings_;
  std::unique_ptr<bootstrap::HostBuffer> constants_, boxes_;
  Image albedo_, normal_, emittance_, depth_, accumulation_;
  VkDescriptorPool pool_ = VK_NULL_HANDLE;
  VkDescriptorSet gbuffer_set_ = VK_NULL_HANDLE, trace_set_ = VK_NULL_HANDLE, resolve_set_ = VK_NULL_HANDLE;
  uint32_t samples_done_ = 0;
  VkQueryPool timestamps_ = VK_NULL_HANDLE;
  double timestamp_period_ns_ = 1.0;
  bool gbuffer_dirty_ = true;
};

}  // namespace statepack::path_tracer
