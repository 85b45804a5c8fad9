// Headless rendering: N samples per pixel into an offscreen target, then the accumulated radiance to
// a file. Same seed, same image, bit for bit.
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <filesystem>

#include "app.hpp"
#include "image_io.hpp"

namespace statepack::path_tracer {

std::unique_ptr<Dearchiver> load_archive(samples::VulkanContext& vk, const std::string& path) {
  auto archive = Archive::from_file(path);
  if (!archive) {
    std::fprintf(stderr, "path_tracer: %s\n", archive.error().message.c_str());
    return nullptr;
  }
  auto dearchiver = Dearchiver::create({vk.physical_device, vk.device});
  if (!dearchiver || !dearchiver->add_archive(std::move(*archive))) return nullptr;
  return std::make_unique<Dearchiver>(std::move(dearchiver.value()));
}

size_t report_validation(const samples::VulkanContext& vk) {
  auto messages = vk.validation_messages();
  for (const auto& m : messages) std::fprintf(stderr, "path_tracer: %s\n", m.c_str());
  return messages.size();
}

namespace {

const char* estimator_name(Estimator e) {
  switch (e) {
    case Estimator::nee:
      return "NEE";
    case Estimator::bsdf:
      return "BSDF sampling";
    case Estimator::mis:
      return "MIS";
    case Estimator::baseline:
      return "tutorial baseline";
  }
  return "?";
}

void progress(uint32_t done, uint32_t total, double seconds) {
  if (!isatty(fileno(stderr))) return;
  constexpr int kWidth = 30;
  int filled = int(double(done) / total * kWidth);
  std::fprintf(stderr, "\r[%.*s%*s] %3u%% %u/%u spp %.1f s", filled, "##############################",
               kWidth - filled, "", done * 100 / total, done, total, seconds);
  if (done == total) std::fprintf(stderr, "\n");
}

}  // namespace

int run_headless(const Options& o) {
  // Refuse an unknown output type before spending the render on it.
  const std::string ext = std::filesystem::path(o.out).extension().string();
  if (ext != ".png" && ext != ".exr" && ext != ".pfm")
    return std::fprintf(stderr, "path_tracer: %s: unknown image type '%s' (use .png, .exr or .pfm)\n",
                        o.out.c_str(), ext.c_str()),
           2;
  auto scene = load_scene(o.scene);
  if (!scene) return std::fprintf(stderr, "path_tracer: %s\n", scene.error().message.c_str()), 1;
  samples::VulkanContextOptions vk_options;
  vk_options.validation = o.validation;
  auto vk = samples::VulkanContext::create(vk_options);
  if (!vk) return std::fprintf(stderr, "path_tracer: %s\n", vk.error().message.c_str()), 1;
  int status = 0;
  {
    auto dearchiver = load_archive(**vk, o.archive);
    if (!dearchiver) return 1;
    constexpr VkFormat kTargetFormat = VK_FORMAT_R8G8B8A8_SRGB;
    auto renderer = Renderer::create(**vk, *dearchiver, o.width, o.height, kTargetFormat);
    if (!renderer) return std::fprintf(stderr, "path_tracer: %s\n", renderer.error().message.c_str()), 1;
    (*renderer)->set_scene(*scene);
    (*renderer)->set_settings(o.settings);

    // The resolve pass draws into an offscreen image of the format the pipeline was patched to.
    auto target =
        samples::create_device_image(**vk, kTargetFormat, o.width, o.height,
                                     VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT);
    if (!target) return std::fprintf(stderr, "path_tracer: %s\n", target.error().message.c_str()), 1;

    auto start = std::chrono::steady_clock::now();
    RenderSettings settings = o.settings;
    while ((*renderer)->samples_done() < o.spp) {
      settings.samples_per_frame =
          std::min(o.settings.samples_per_frame, o.spp - (*renderer)->samples_done());
      (*renderer)->set_settings(settings);
      auto done = (*vk)->submit_and_wait([&](VkCommandBuffer cmd) {
        (*renderer)->record(cmd, (*target)->image, (*target)->view, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL);
      });
      if (!done) {
        std::fprintf(stderr, "path_tracer: %s\n", done.error().message.c_str());
        status = 1;
        break;
      }
      progress((*renderer)->samples_done(), o.spp,
               std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
    }
    double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    if (status == 0) {
      auto radiance = (*renderer)->read_accumulation();
      if (!radiance) {
        std::fprintf(stderr, "path_tracer: %s\n", radiance.error().message.c_str());
        status = 1;
      } else if (std::string error = write_image(o.out, *radiance, o.width, o.height, o.settings.exposure);
                 !error.empty()) {
        std::fprintf(stderr, "path_tracer: %s: %s\n", o.out.c_str(), error.c_str());
        status = 1;
      } else {
        std::printf(
            "path_tracer: %ux%u, %u spp, %u bounces, %s, seed %u: %.2f s (%.1f ms per sample) -> %s\n",
            o.width, o.height, o.spp, o.settings.bounces, estimator_name(o.settings.estimator),
            o.settings.seed, seconds, 1000.0 * seconds / o.spp, o.out.c_str());
      }
    }
  }
  (*vk)->destroy_device();
  if (report_validation(**vk) > 0) status = 1;
  return status;
}

}  // namespace statepack::path_tracer
