#include "live_reload.hpp"

#include <chrono>
#include <cstdio>

#include "app.hpp"

namespace statepack::path_tracer {

std::unique_ptr<LiveReload> LiveReload::start(const std::string& archive) {
  auto watch = ArchiveFileWatch::create(archive);
  if (!watch) {
    std::fprintf(stderr, "path_tracer: --watch: %s\n", printable(watch.error().message).c_str());
    return nullptr;
  }
  std::printf("path_tracer: watching %s for new builds\n", printable(archive).c_str());
  std::fflush(stdout);  // a script waiting for this line may read a pipe or a file
  return std::unique_ptr<LiveReload>(new LiveReload(std::move(*watch)));
}

bool LiveReload::poll(Dearchiver& dearchiver, VkDevice device) {
  auto polled = watch_.poll();
  if (!polled) {
    std::fprintf(stderr, "path_tracer: not reloaded: %s\n", printable(polled.error().message).c_str());
    return false;
  }
  if (!*polled) return false;
  const auto start = std::chrono::steady_clock::now();
  auto report = dearchiver.reload(std::move(**polled));
  if (!report) {
    std::fprintf(stderr, "path_tracer: not reloaded: %s\n", printable(report.error().message).c_str());
    return false;
  }
  const double ms =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  std::string recreated;
  for (const auto& name : report->recreated)
    recreated += (recreated.empty() ? "'" : ", '") + printable(name) + "'";
  std::printf("path_tracer: reload %u of %s in %.1f ms: re-created %zu [%s], kept %zu\n", ++reloads_,
              printable(watch_.path().string()).c_str(), ms, report->recreated.size(), recreated.c_str(),
              report->kept.size());
  for (const auto& f : report->failures)
    std::fprintf(stderr, "path_tracer: kept the old '%s': %s\n", printable(f.object.name).c_str(),
                 printable(f.error.message).c_str());
  std::fflush(stdout);
  if (report->recreated.empty()) return false;
  vkDeviceWaitIdle(device);  // a frame in flight may still use the replaced pipelines
  dearchiver.destroy_retired(report->generation);
  return true;
}

}  // namespace statepack::path_tracer
