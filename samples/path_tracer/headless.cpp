// Headless rendering: N samples per pixel into an offscreen target, then the accumulated radiance to
// a file. Same seed, same image, bit for bit.
#include <unistd.h>

#include <cstdio>
#include <filesystem>

#include "app.hpp"
#include "image_io.hpp"
#include "live_reload.hpp"
#include "offline.hpp"

namespace statepack::path_tracer {

namespace {

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
                        printable(o.out).c_str(), printable(ext).c_str()),
           2;
  if (std::string refused = bootstrap::output_refusal(o.out, {o.scene, o.archive}); !refused.empty())
    return std::fprintf(stderr, "path_tracer: --out: %s\n", printable(refused).c_str()), 2;
  auto scene = load_scene(o.scene);
  if (!scene) return std::fprintf(stderr, "path_tracer: %s\n", printable(scene.error().message).c_str()), 1;
  bootstrap::VulkanContextOptions vk_options;
  vk_options.validation = o.validation;
  auto vk = bootstrap::VulkanContext::create(vk_options);
  if (!vk) return std::fprintf(stderr, "path_tracer: %s\n", printable(vk.error().message).c_str()), 1;
  int status = 0;
  {
    auto dearchiver = load_archive(**vk, o.archive);
    if (!dearchiver) return 1;
    std::unique_ptr<LiveReload> live = o.watch ? LiveReload::start(o.archive) : nullptr;
    if (o.watch && !live) return 1;
    auto reloaded = [&] { return live->poll(*dearchiver, (*vk)->device); };
    auto rendered = render_offline(**vk, *dearchiver, *scene, o.settings, o.width, o.height, o.spp, progress,
                                   live ? std::function<bool()>(reloaded) : std::function<bool()>());
    if (!rendered) {
      std::fprintf(stderr, "path_tracer: %s\n", printable(rendered.error().message).c_str());
      status = 1;
    } else if (std::string error = write_image(o.out, rendered->rgba, o.width, o.height, o.settings.exposure,
                                               {o.scene, o.archive});
               !error.empty()) {
      std::fprintf(stderr, "path_tracer: %s: %s\n", printable(o.out).c_str(), printable(error).c_str());
      status = 1;
    } else {
      std::printf(
          "path_tracer: %ux%u, %u spp, %u bounces, %s, %s sampler, seed %u: %.2f s (%.1f ms per "
          "sample) -> %s\n",
          o.width, o.height, o.spp, o.settings.bounces, names_of(o.settings.estimator).title,
          names_of(o.settings.sampler).title, o.settings.seed, rendered->seconds,
          1000.0 * rendered->seconds / o.spp, printable(o.out).c_str());
    }
  }
  (*vk)->destroy_device();
  if (report_validation(**vk) > 0) status = 1;
  return status;
}

}  // namespace statepack::path_tracer
