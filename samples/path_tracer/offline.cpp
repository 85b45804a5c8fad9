#include "offline.hpp"

#include <algorithm>
#include <chrono>
#include <cstdio>

#include "app.hpp"

namespace statepack::path_tracer {

std::unique_ptr<Dearchiver> load_archive(bootstrap::VulkanContext& vk, const std::string& path) {
  auto archive = Archive::from_file(path);
  if (!archive) {
    std::fprintf(stderr, "path_tracer: %s\n", printable(archive.error().message).c_str());
    return nullptr;
  }
  auto dearchiver = Dearchiver::create(vk.device_context());  // the features the device was made with
  if (!dearchiver || !dearchiver->add_archive(std::move(*archive))) return nullptr;
  return std::make_unique<Dearchiver>(std::move(dearchiver.value()));
}

size_t report_validation(const bootstrap::VulkanContext& vk) {
  auto messages = vk.validation_messages();
  for (const auto& m : messages) std::fprintf(stderr, "path_tracer: %s\n", printable(m).c_str());
  return messages.size();
}

Result<OfflineRender> render_offline(bootstrap::VulkanContext& vk, Dearchiver& dearchiver, const Scene& scene,
                                     const RenderSettings& settings, uint32_t width, uint32_t height,
                                     uint32_t spp,
                                     const std::function<void(uint32_t, uint32_t, double)>& progress,
                                     const std::function<bool()>& between_batches) {
  // The resolve pass draws into an offscreen image of the format the pipeline is patched to.
  constexpr VkFormat kTargetFormat = VK_FORMAT_R8G8B8A8_SRGB;
  auto renderer = Renderer::create(vk, dearchiver, width, height, kTargetFormat);
  if (!renderer) return renderer.error();
  auto target =
      bootstrap::create_device_image(vk, kTargetFormat, width, height,
                                     VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT);
  if (!target) return target.error();
  if (auto ok = (*renderer)->set_scene(scene); !ok) return ok.error();
  (*renderer)->set_settings(settings);
  OfflineRender out;
  using Clock = std::chrono::steady_clock;
  const auto start = Clock::now();
  RenderSettings batch = settings;
  while ((*renderer)->samples_done() < spp) {
    batch.samples_per_frame = std::min(settings.samples_per_frame, spp - (*renderer)->samples_done());
    (*renderer)->set_settings(batch);
    const auto batch_start = Clock::now();
    auto done = vk.submit_and_wait([&](VkCommandBuffer cmd) {
      (*renderer)->record(cmd, (*target)->image, (*target)->view, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL);
    });
    if (!done) return done.error();
    out.batch_wall_ms.push_back(
        std::chrono::duration<double, std::milli>(Clock::now() - batch_start).count());
    out.batch_gpu_ms.push_back((*renderer)->last_trace_ms());
    if (progress)
      progress((*renderer)->samples_done(), spp, std::chrono::duration<double>(Clock::now() - start).count());
    if (between_batches && between_batches()) (*renderer)->restart_accumulation();
  }
  out.seconds = std::chrono::duration<double>(Clock::now() - start).count();
  auto radiance = (*renderer)->read_accumulation();
  if (!radiance) return radiance.error();
  out.rgba = std::move(radiance.value());
  return out;
}

}  // namespace statepack::path_tracer
