// statepack verify: "will this archive work on this machine?" Loads each archive, unpacks every object
// on a local Vulkan device with the validation layer on (when installed), prints one line per object,
// and fails on any error or validation message. Like fossilize-replay, it can warm a pipeline cache.
#pragma once

#include <cstdint>
#include <filesystem>
#include <iosfwd>
#include <optional>
#include <string>
#include <vector>

#include <vulkan/vulkan_core.h>

namespace statepack::packager {

struct VerifyOptions {
  std::vector<std::filesystem::path> archives;
  int device_index = -1;   // -1: the first Vulkan 1.3 device
  bool validation = true;  // the layer when installed (a note when it is not)
  // Render targets the archive leaves UNKNOWN (patched at run time) are verified with these formats.
  VkFormat color_format = VK_FORMAT_R8G8B8A8_UNORM;
  std::optional<std::filesystem::path> cache;  // pipeline cache to load (if present) and save
  // A variants file (Dearchiver::save_variants): create exactly these patched pipelines, each from the
  // first archive that has its pipeline, instead of every object of the archives.
  std::optional<std::filesystem::path> variants;
  // Objects are created in worker processes (this program again, with --worker-start) so that a driver
  // that crashes or hangs fails only the object it was creating; a worker that reports nothing for
  // this long is killed. 0: create everything in this process, with no time limit.
  unsigned timeout_seconds = 60;
  // Set in a worker: where to start (archive and object index), and its channel to the supervisor.
  struct Position {
    size_t archive = 0, object = 0;
  };
  std::optional<Position> worker_start;
};

// The file descriptor a worker reports its progress on (verify_supervisor.cpp has the protocol).
inline constexpr int kVerifyControlFd = 3;
// The socket a worker waits on after `done A`: the supervisor sends one byte once it has printed archive
// A's summary, so that the worker's next lines come after it on the shared stdout.
inline constexpr int kVerifyAckFd = 4;

// What verify counts per archive and in all: objects, those ok, and the pipelines those created
// (PipelineCreation's fields, summed).
struct VerifyTotals {
  size_t objects = 0, ok = 0;
  size_t pipelines = 0, with_feedback = 0, cache_hits = 0;
  int64_t time_ns = 0, driver_ns = 0;
  void add(size_t count, int64_t time, int64_t driver, size_t feedback, size_t hits) {
    pipelines += count, time_ns += time, driver_ns += driver, with_feedback += feedback, cache_hits += hits;
  }
  void add(const VerifyTotals& o) {
    objects += o.objects, ok += o.ok;
    add(o.pipelines, o.time_ns, o.driver_ns, o.with_feedback, o.cache_hits);
  }
  // "2 of 2 objects ok; 2 pipelines created in 0.61 ms (the driver's feedback: 0.55 ms, 1 from the
  // pipeline cache)"
  std::string summary() const;
};
// Whether verify ends with an "in all:" line: for several archives, and for one when variants resolved to
// none of its pipelines (they count, and its own line does not show them). run_verify and the supervisor
// both print it.
inline bool wants_in_all_line(size_t archives, size_t unresolved_variants) {
  return archives > 1 || unresolved_variants > 0;
}

// Returns an ExitCode: 0 every object unpacked without a validation message, 1 an object failed or the
// layer spoke, 2 usage, 3 an archive could not be read or no device could be created.
int run_verify(const VerifyOptions& options, std::ostream& out, std::ostream& err);
// The same in worker processes (run_verify calls it unless timeout_seconds is 0 or this is a worker).
int supervise_verify(const VerifyOptions& options, std::ostream& out, std::ostream& err);

// Vulkan's name for a format ("R8G8B8A8_UNORM", as VK_FORMAT_ spells it) and back.
std::optional<VkFormat> parse_vk_format(const std::string& name);

}  // namespace statepack::packager
