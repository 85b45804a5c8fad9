// --watch: the archive reloaded while the path tracer runs, so that a shader saved beside a running
// `statepack pack --watch` shows up in the image without a restart (and without a shader compiler here).
#pragma once

#include <memory>
#include <string>

#include "statepack/dearchiver.hpp"

namespace statepack::path_tracer {

class LiveReload {
 public:
  // Watches the archive file; null (and a message) when it cannot.
  static std::unique_ptr<LiveReload> start(const std::string& archive);
  // Reloads a new, complete build of the archive into `dearchiver` when one was written (one line says
  // what changed) and destroys the replaced pipelines once `device` is idle. True when a pipeline
  // changed: the caller restarts the accumulation. A failed reload keeps the old pipelines and says why.
  bool poll(Dearchiver& dearchiver, VkDevice device);

 private:
  explicit LiveReload(ArchiveFileWatch watch) : watch_(std::move(watch)) {}
  ArchiveFileWatch watch_;
  unsigned reloads_ = 0;
};

}  // namespace statepack::path_tracer
