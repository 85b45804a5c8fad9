// The development loop, timed: `statepack pack --watch` runs on a copy of the path tracer's notation and
// shaders, this program holds the path tracer's pipelines (patched as the path tracer patches them) and
// polls the archive with ArchiveFileWatch, and the path-tracing shader is saved (by rename, as editors
// do) again and again. Each edit is timed from the save to Dearchiver::reload having swapped the new
// pipelines in: what a developer waits for. Also the cost of a poll that finds nothing new.
//
// Usage: reload_benchmark <statepack> <source dir> <edits>
#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>
#include <thread>
#include <vector>

#include "arguments.hpp"
#include "statepack/bootstrap/host_tools.hpp"
#include "statepack/bootstrap/vulkan_context.hpp"
#include "statepack/dearchiver.hpp"

extern char** environ;

namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;
using statepack::bootstrap::printable;

std::string read_text(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), {}};
}

// Saved as an editor saves: a temporary beside the file, renamed over it.
void save(const fs::path& path, const std::string& text) {
  const fs::path temporary = path.string() + ".swp";
  std::ofstream(temporary, std::ios::binary | std::ios::trunc) << text;
  fs::rename(temporary, path);
}

double percentile(std::vector<double> v, double p) {
  std::sort(v.begin(), v.end());
  return v[std::min(v.size() - 1, size_t(p * double(v.size() - 1) + 0.5))];
}

int fail(const std::string& what) {
  std::fprintf(stderr, "reload_benchmark: %s\n", printable(what).c_str());
  return 1;
}

}  // namespace

int main(int argc, char** argv) {
  const auto edits = argc == 4 ? statepack::benchmarks::positive_count(argv[3], 1000) : std::nullopt;
  if (!edits) return std::fprintf(stderr, "usage: reload_benchmark <statepack> <source dir> <edits>\n"), 2;
  const fs::path packer = argv[1], source = argv[2];
  const fs::path dir = fs::temp_directory_path() / ("statepack_reload_bench_" + std::to_string(getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  fs::copy(source / "shaders", dir / "shaders", fs::copy_options::recursive);
  fs::copy(source / "states", dir, fs::copy_options::recursive);
  const fs::path archive = dir / "path_tracer.spk", shader = dir / "shaders/path_tracer/path_trace.comp";
  const std::string original = read_text(shader);
  const std::string store = "imageStore(accumulation, pixel, vec4(mean, 1.0));";
  const size_t at = original.find(store);
  if (at == std::string::npos) return fail("the path-tracing shader no longer has the line this edits");

  // The resident packer, its output to a log.
  const std::string log = (dir / "watch.log").string(), input = (dir / "path_tracer.json").string(),
                    shaders = (dir / "shaders").string(), out = archive.string();
  std::vector<std::string> args = {packer.string(), "pack", "--vulkan", "-s",     shaders, "-i",
                                   input,           "-o",   out,        "--watch"};
  std::vector<char*> argv_watch;
  for (auto& a : args) argv_watch.push_back(a.data());
  argv_watch.push_back(nullptr);
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addopen(&actions, 1, log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  posix_spawn_file_actions_adddup2(&actions, 1, 2);
  pid_t watcher = 0;
  if (posix_spawn(&watcher, argv_watch[0], &actions, nullptr, argv_watch.data(), environ) != 0)
    return fail("cannot start " + packer.string());
  posix_spawn_file_actions_destroy(&actions);
  for (int i = 0; i < 600 && !fs::exists(archive); ++i)
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  if (!fs::exists(archive))
    return kill(watcher, SIGINT), fail("the first pack wrote no archive: " + read_text(log));

  statepack::bootstrap::VulkanContextOptions options;
  options.validation = false;  // timing: the layer's own cost is not the loop's
  auto vk = statepack::bootstrap::VulkanContext::create(options);
  if (!vk) return kill(watcher, SIGINT), fail(vk.error().message);
  int status = 0;
  {
    auto dearchiver = statepack::Dearchiver::create((*vk)->device_context());
    auto loaded = statepack::Archive::from_file(archive);
    auto watch = statepack::ArchiveFileWatch::create(archive);
    if (!dearchiver || !loaded || !watch || !dearchiver->add_archive(std::move(*loaded)))
      return kill(watcher, SIGINT), fail("cannot load the archive");
    // Every pipeline, the resolve target's format patched in as the path tracer does.
    auto made = dearchiver->unpack_all([](const statepack::ObjectInfo&, statepack::PatchableState& s) {
      for (uint32_t i = 0; i < s.color_count; ++i)
        if (s.color_formats[i] == VK_FORMAT_UNDEFINED) s.color_formats[i] = VK_FORMAT_R8G8B8A8_SRGB;
    });
    if (!made) return kill(watcher, SIGINT), fail(made.error().message);

    // A poll that finds nothing new.
    constexpr int kPolls = 100000;
    const auto poll_start = Clock::now();
    for (int i = 0; i < kPolls; ++i)
      if (auto p = watch->poll(); !p || *p)
        return kill(watcher, SIGINT), fail("the archive changed by itself");
    const double poll_ns =
        std::chrono::duration<double, std::nano>(Clock::now() - poll_start).count() / kPolls;

    std::vector<double> seconds;
    std::vector<size_t> recreated, kept;
    for (int e = 1; e <= *edits && status == 0; ++e) {
      std::string text = original;
      text.replace(at, store.size(),
                   "imageStore(accumulation, pixel, vec4(mean, " + std::to_string(e + 1) + ".0));");
      const auto saved = Clock::now();
      save(shader, text);
      for (;;) {
        auto polled = watch->poll();
        if (!polled) return kill(watcher, SIGINT), fail(polled.error().message);
        if (*polled) {
          auto report = dearchiver->reload(std::move(**polled));
          if (!report || !report->ok()) return kill(watcher, SIGINT), fail("reload failed");
          seconds.push_back(std::chrono::duration<double>(Clock::now() - saved).count());
          recreated.push_back(report->recreated.size());
          kept.push_back(report->kept.size());
          if (e == 1) {
            std::printf("edit 1 re-created:");
            for (const auto& n : report->recreated) std::printf(" '%s'", printable(n).c_str());
            std::printf("; kept %zu\n", report->kept.size());
          }
          vkDeviceWaitIdle((*vk)->device);
          dearchiver->destroy_retired();
          break;
        }
        if (Clock::now() - saved > std::chrono::seconds(60)) {
          status = fail("no new archive 60 s after the save: " + read_text(log));
          break;
        }
        std::this_thread::sleep_for(std::chrono::milliseconds(1));
      }
    }
    if (status == 0) {
      std::printf(
          "%d edits of path_trace.comp, save -> new pipelines in the running program (pack --watch, "
          "ArchiveFileWatch polled every 1 ms, Dearchiver::reload):\n",
          *edits);
      std::printf("  median %.3f s, 90th percentile %.3f s, max %.3f s\n", percentile(seconds, 0.5),
                  percentile(seconds, 0.9), percentile(seconds, 1.0));
      std::printf("  pipelines re-created per edit: %zu to %zu (kept %zu)\n",
                  *std::min_element(recreated.begin(), recreated.end()),
                  *std::max_element(recreated.begin(), recreated.end()), kept.front());
      std::printf("  a poll that finds nothing new: %.0f ns (mean of %d)\n", poll_ns, kPolls);
    }
  }
  kill(watcher, SIGINT);
  int watch_status = 0;
  waitpid(watcher, &watch_status, 0);
  fs::remove_all(dir);
  return status;
}
