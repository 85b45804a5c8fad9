#include "verify.hpp"

#include <unistd.h>

#include <algorithm>
#include <bit>
#include <cerrno>
#include <cstdio>
#include <ostream>
#include <set>

#include "format/archive_file.hpp"
#include "layout/format_support.hpp"
#include "notation/diagnostics.hpp"
#include "notation/enum_tables.hpp"
#include "pack/packer.hpp"
#include "runtime/archive_access.hpp"
#include "statepack/bootstrap/vulkan_context.hpp"
#include "statepack/dearchiver.hpp"
#include "support/output_files.hpp"
#include "support/suggest.hpp"

namespace statepack::packager {
namespace {

const char* kind_name(ObjectKind kind) {
  switch (kind) {
    case ObjectKind::graphics_pipeline:
      return "graphics pipeline";
    case ObjectKind::compute_pipeline:
      return "compute pipeline";
    case ObjectKind::resource_signature:
      return "resource signature";
    case ObjectKind::render_pass:
      return "render pass";
    case ObjectKind::shader:
      return "shader";
  }
  return "object";
}

// What verify creates: an object of an archive, or a recorded variant of a pipeline (--variants).
struct Task {
  ObjectInfo object;
  const PipelineVariant* variant = nullptr;
};

// Creates one task's object. A pipeline comes back (null for other objects). `patched_slots` receives
// the render targets the archive leaves to run time (UNKNOWN, or absent while the pixel shader writes
// them), which the application must set: verify shows them.
Result<const UnpackedPipeline*> unpack_one(Dearchiver& dearchiver, const Task& task, VkFormat color_format,
                                           std::vector<uint32_t>& patched_slots) {
  const ObjectInfo& object = task.object;
  if (task.variant) return dearchiver.unpack_variant(*task.variant);
  switch (object.kind) {
    case ObjectKind::graphics_pipeline:
      // A render target left UNKNOWN is patched at run time (a swapchain format): verify it with one.
      return dearchiver.unpack_graphics(object.name, [&](PatchableState& s) {
        // Targets the notation leaves to run time (the pixel shader writes more than it gives) are
        // added as the application's callback would add them.
        const uint32_t written = uint32_t(32 - std::countl_zero(s.written_color_targets));
        if (written > s.color_count && written <= s.color_formats.size()) s.color_count = written;
        for (uint32_t i = 0; i < s.color_count && i < s.color_formats.size(); ++i)
          if (s.color_formats[i] == VK_FORMAT_UNDEFINED) {
            s.color_formats[i] = color_format;
            patched_slots.push_back(i);
          }
      });
    case ObjectKind::compute_pipeline:
      return dearchiver.unpack_compute(object.name);
    case ObjectKind::resource_signature:
      if (auto r = dearchiver.unpack_signature(object.name); !r) return r.error();
      break;
    case ObjectKind::render_pass:
      if (auto r = dearchiver.unpack_render_pass(object.name); !r) return r.error();
      break;
    case ObjectKind::shader:
      if (auto r = dearchiver.unpack_shader(object.name); !r) return r.error();
      break;
  }
  return static_cast<const UnpackedPipeline*>(nullptr);
}

std::string milliseconds(int64_t ns) {
  char text[32];
  std::snprintf(text, sizeof text, "%.2f ms", double(ns) / 1e6);
  return text;
}

// ": created in 0.31 ms (the driver's feedback: 0.29 ms, from the pipeline cache)"
std::string creation_text(const PipelineCreation& c) {
  std::string text = ": created in " + milliseconds(c.time.count());
  if (c.feedback)
    text += " (the driver's feedback: " + milliseconds(c.driver_time.count()) +
            (c.cache_hit ? ", from the pipeline cache)" : ")");
  return text;
}

}  // namespace

std::string VerifyTotals::summary() const {
  std::string text = std::to_string(ok) + " of " + std::to_string(objects) + " objects ok";
  if (pipelines == 0) return text;
  text += "; " + std::to_string(pipelines) + (pipelines == 1 ? " pipeline" : " pipelines") + " created in " +
          milliseconds(time_ns);
  if (with_feedback)
    text += " (the driver's feedback: " + milliseconds(driver_ns) + ", " + std::to_string(cache_hits) +
            " from the pipeline cache)";
  return text;
}

std::optional<VkFormat> parse_vk_format(const std::string& name) {
  std::string bare = name.starts_with("VK_FORMAT_") ? name.substr(10) : name;
  // The notation's names (RGBA8_UNORM) first, then Vulkan's own for the formats the notation has.
  for (const auto& [text, value] : kTextureFormats)
    if (text == bare && value != VK_FORMAT_UNDEFINED && value != kUnsupportedValue) return VkFormat(value);
  return std::nullopt;
}

namespace {

// What a worker tells its supervisor (verify_supervisor.cpp), a line per event; nothing in-process.
class Progress {
 public:
  explicit Progress(bool worker) : fd_(worker ? kVerifyControlFd : -1) {}
  bool worker() const { return fd_ >= 0; }
  void send(const std::string& line) const {
    if (fd_ < 0) return;
    const std::string text = line + '\n';
    for (size_t done = 0; done < text.size();) {
      const ssize_t n = ::write(fd_, text.data() + done, text.size() - done);
      if (n < 0 && errno == EINTR) continue;
      if (n <= 0) return;  // the supervisor is gone: the output still goes to stdout
      done += size_t(n);
    }
  }
  // After `done`: waits until the supervisor has printed the archive's summary (or is gone).
  void wait_for_ack() const {
    if (fd_ < 0) return;
    char byte = 0;
    while (::read(kVerifyAckFd, &byte, 1) < 0 && errno == EINTR) {
    }
  }

 private:
  int fd_;
};

// The validation messages since the last call.
class MessageCursor {
 public:
  explicit MessageCursor(const bootstrap::VulkanContext& vk) : vk_(vk) {}
  std::vector<std::string> fresh() {
    auto all = vk_.validation_messages();
    std::vector<std::string> result(all.begin() + std::ptrdiff_t(std::min(seen_, all.size())), all.end());
    seen_ = all.size();
    return result;
  }

 private:
  const bootstrap::VulkanContext& vk_;
  size_t seen_ = 0;
};

std::string describe(const Task& task, const std::vector<uint32_t>& patched_slots, VkFormat format) {
  const ObjectInfo& object = task.object;
  std::string what = std::string(kind_name(object.kind)) + " '" + printable(object.name) + "'";
  if (task.variant)
    what += task.variant->state == "{}" ? " as archived" : " with " + printable(task.variant->state);
  if (!patched_slots.empty()) {
    what += " (render target";
    for (size_t i = 0; i < patched_slots.size(); ++i)
      what += (i ? ", " : patched_slots.size() > 1 ? "s " : " ") + std::to_string(patched_slots[i]);
    what += ", set at run time: verified as " + format_name(format) + ")";
  }
  return what;
}

// What verify creates of one archive: every object, or the variants that resolve to it.
std::vector<Task> tasks_of(const Archive& archive, size_t index, const VerifyOptions& options,
                           const std::vector<PipelineVariant>& variants, const std::vector<size_t>& owner) {
  std::vector<Task> tasks;
  if (!options.variants) {
    for (auto& object : archive.objects()) tasks.push_back({std::move(object)});
    return tasks;
  }
  for (size_t v = 0; v < variants.size(); ++v)
    if (owner[v] == index) tasks.push_back({{variants[v].pipeline, variants[v].kind}, &variants[v]});
  return tasks;
}

// Unpacks the tasks of one archive from `first_object` on; returns the exit code it earned.
int verify_archive(size_t index, const std::filesystem::path& path, size_t first_object,
                   const DeviceContext& context, const VerifyOptions& options,
                   const std::vector<PipelineVariant>& variants, const std::vector<size_t>& owner,
                   MessageCursor& messages, const Progress& progress, VerifyTotals& all, std::ostream& out,
                   std::ostream& err) {
  auto archive = Archive::from_file(path);
  if (!archive) {
    err << "statepack: error: " << printable(archive.error().message) << '\n';
    return kExitIoError;
  }
  // Archive checks what Vulkan uses; the OpenGL block, which verify does not create, is checked too.
  if (auto gl = format::check_opengl(detail::ArchiveAccess::contents(*archive), path.string()); !gl) {
    err << "statepack: error: " << printable(gl.error().message) << '\n';
    return kExitInputError;
  }
  const std::vector<Task> tasks = tasks_of(*archive, index, options, variants, owner);
  progress.send("archive " + std::to_string(index) + " " + std::to_string(tasks.size()));
  int exit_code = kExitSuccess;
  VerifyTotals totals;
  totals.objects = tasks.size();
  std::set<const UnpackedPipeline*> counted;
  {
    auto dearchiver = Dearchiver::create(context);
    if (!dearchiver || !dearchiver->add_archive(std::move(*archive))) {
      err << "statepack: error: " << printable(path.string()) << ": cannot create the dearchiver\n";
      return kExitInputError;
    }
    for (size_t i = first_object; i < tasks.size(); ++i) {
      const Task& task = tasks[i];
      const std::string place = std::to_string(index) + " " + std::to_string(i);
      progress.send("begin " + place + " " + describe(task, {}, options.color_format));
      std::vector<uint32_t> patched_slots;
      auto unpacked = unpack_one(*dearchiver, task, options.color_format, patched_slots);
      auto fresh = messages.fresh();
      const std::string what = describe(task, patched_slots, options.color_format);
      // Performance warnings are advice: the object is valid, and is reported ok with them.
      const bool only_advice = std::all_of(fresh.begin(), fresh.end(), [](const std::string& m) {
        return m.starts_with(bootstrap::kPerformanceWarning);
      });
      VerifyTotals made;
      // A pipeline made before (two variants that settle alike) is reported again but counted once.
      if (unpacked && *unpacked && counted.insert(*unpacked).second) {
        const PipelineCreation& c = (*unpacked)->creation;
        made.add(1, c.time.count(), c.feedback ? c.driver_time.count() : 0, c.feedback, c.cache_hit);
      }
      if (unpacked && only_advice) {
        out << "ok     " << what << (*unpacked ? creation_text((*unpacked)->creation) : "") << '\n';
        for (const auto& m : fresh) out << "         warning: " << printable(m) << '\n';
        ++totals.ok;
        totals.add(made);
      } else {
        exit_code = kExitInputError;
        out << "FAILED " << what << ": "
            << (unpacked ? "validation messages" : printable(unpacked.error().message)) << '\n';
        for (const auto& m : fresh) out << "         " << printable(m) << '\n';
      }
      out.flush();  // before the supervisor hears of it: its own lines come after
      const bool passed = unpacked && only_advice;
      progress.send("end " + place + (passed ? " ok " : " failed ") + std::to_string(made.pipelines) + " " +
                    std::to_string(made.time_ns) + " " + std::to_string(made.driver_ns) + " " +
                    std::to_string(made.with_feedback) + " " + std::to_string(made.cache_hits));
    }
  }  // the dearchiver destroys its objects here; the layer reports anything left behind
  if (auto leaks = messages.fresh(); !leaks.empty()) {
    exit_code = kExitInputError;
    for (const auto& m : leaks) out << "FAILED " << printable(path.string()) << ": " << printable(m) << '\n';
  }
  out.flush();
  all.add(totals);
  if (progress.worker()) {
    progress.send("done " + std::to_string(index));  // the supervisor counts and prints the summary
    progress.wait_for_ack();
  } else
    out << printable(path.string()) << ": " << totals.summary() << '\n';
  return exit_code;
}

// Each variant's archive: the first (in command-line order) with a pipeline of its name, as a
// Dearchiver holding them all resolves it (a kind that differs is then wrong_type); archives.size() for
// none. Each worker reads the archives' names again: a cost of --variants, paid before the device.
// `all_names` gets every pipeline name of the archives, for "did you mean" on a variant that resolves
// to none.
std::vector<size_t> owners_of(const std::vector<PipelineVariant>& variants, const VerifyOptions& options,
                              std::vector<std::string>& all_names) {
  std::vector<size_t> owner(variants.size(), options.archives.size());
  std::set<std::string, std::less<>> every;
  for (size_t a = options.archives.size(); a-- > 0;) {  // the last first, so the first wins
    auto archive = Archive::from_file(options.archives[a]);
    if (!archive) continue;  // verify_archive reports it
    std::set<std::string, std::less<>> names;
    for (const auto& o : archive->objects())
      if (o.kind == ObjectKind::graphics_pipeline || o.kind == ObjectKind::compute_pipeline)
        names.insert(o.name);
    for (size_t v = 0; v < variants.size(); ++v)
      if (names.count(variants[v].pipeline)) owner[v] = a;
    every.insert(names.begin(), names.end());
  }
  all_names.assign(every.begin(), every.end());
  return owner;
}

// The pipeline cache is verify's one output: it may not replace an input of the run (an archive, the
// variants file) however the path reaches it (the same path, `..`, a symlink, a hard link), nor be a
// link or anything but a regular file. Empty when it may be written.
std::string cache_refusal(const VerifyOptions& options) {
  std::vector<detail::InputFile> inputs;
  auto protect = [&](const std::filesystem::path& path) {
    if (auto id = detail::file_identity(path)) inputs.push_back({path, *id});
  };
  for (const auto& archive : options.archives) protect(archive);
  if (options.variants) protect(*options.variants);
  return detail::OutputSet(std::move(inputs)).refuse_reason(*options.cache);
}

}  // namespace

int run_verify(const VerifyOptions& options, std::ostream& out, std::ostream& err) {
  // Before any work: a run that could only end by destroying an input does not start.
  if (options.cache && !options.worker_start)
    if (std::string reason = cache_refusal(options); !reason.empty()) {
      err << "statepack: error: --cache: " << printable(reason) << '\n';
      return kExitUsage;
    }
  if (!options.worker_start && options.timeout_seconds > 0) return supervise_verify(options, out, err);
  const Progress progress(options.worker_start.has_value());
  const VerifyOptions::Position start = options.worker_start.value_or(VerifyOptions::Position{});
  const bool first = start.archive == 0 && start.object == 0;  // a restarted worker says nothing twice
  bootstrap::VulkanContextOptions vk_options;
  vk_options.validation = options.validation;
  vk_options.validation_if_present = true;
  vk_options.device_index = options.device_index;
  vk_options.enable_supported_features = true;
  auto vk = bootstrap::VulkanContext::create(vk_options);
  if (!vk) {
    err << "statepack: error: cannot create a Vulkan device: " << printable(vk.error().message) << '\n';
    return kExitIoError;
  }
  if (first)
    out << "device: " << printable((*vk)->device_name) << " (" << printable((*vk)->driver_name) << ")"
        << ((*vk)->validation_enabled ? ", validation layer on" : "") << '\n';
  if (first && options.validation && !(*vk)->validation_enabled)
    err << "statepack: note: the Vulkan validation layer is not installed; objects are only created "
           "(apt-get install vulkan-validationlayers)\n";

  DeviceContext context = (*vk)->device_context();
  std::optional<PipelineCacheLoad> cache;
  if (options.cache) {
    auto loaded = load_pipeline_cache(context, *options.cache);
    if (!loaded) {
      err << "statepack: error: " << printable(loaded.error().message) << '\n';
      return kExitIoError;
    }
    cache = *loaded;
    context.pipeline_cache = cache->cache;
    if (first && !cache->reused && !cache->reason.empty())
      out << "pipeline cache: starting empty (" << printable(cache->reason) << ")\n";
  }
  int exit_code = kExitSuccess;
  size_t unresolved = 0;  // variants whose pipeline no archive has
  std::vector<PipelineVariant> variants;
  std::vector<size_t> owner;
  if (options.variants) {
    auto loaded = load_variants(*options.variants);
    if (!loaded) {
      err << "statepack: error: " << printable(loaded.error().message) << '\n';
      return loaded.error().code == ErrorCode::io_error ? kExitIoError : kExitInputError;
    }
    variants = std::move(*loaded);
    std::vector<std::string> names;
    owner = owners_of(variants, options, names);
    for (size_t v = 0; v < variants.size(); ++v)
      if (owner[v] == options.archives.size()) {
        exit_code = kExitInputError;
        ++unresolved;
        if (first)
          out << "FAILED " << describe({{variants[v].pipeline, variants[v].kind}, &variants[v]}, {}, {})
              << ": " << variants[v].origin << "/pipeline: no archive given has a pipeline named '"
              << printable(variants[v].pipeline) << "'" << detail::did_you_mean(variants[v].pipeline, names)
              << '\n';
      }
  }
  progress.send("ready " + std::to_string(unresolved));

  MessageCursor messages(**vk);
  VerifyTotals all;
  all.objects = unresolved;
  for (size_t i = start.archive; i < options.archives.size(); ++i) {
    const size_t first_object = i == start.archive ? start.object : 0;
    exit_code = std::max(exit_code, verify_archive(i, options.archives[i], first_object, context, options,
                                                   variants, owner, messages, progress, all, out, err));
  }
  if (!progress.worker() && wants_in_all_line(options.archives.size(), unresolved))
    out << "in all: " << all.summary() << '\n';
  if (cache) {
    if (auto saved = save_pipeline_cache(context, cache->cache, *options.cache); !saved) {
      err << "statepack: error: " << printable(saved.error().message) << '\n';
      exit_code = std::max(exit_code, int(kExitIoError));
    } else {
      out << "pipeline cache: written to " << printable(options.cache->string()) << '\n';
    }
    vkDestroyPipelineCache((*vk)->device, cache->cache, nullptr);
  }
  (*vk)->destroy_device();
  if (auto last = messages.fresh(); !last.empty()) {
    exit_code = std::max(exit_code, int(kExitInputError));
    for (const auto& m : last) out << "FAILED device teardown: " << printable(m) << '\n';
  }
  return exit_code;
}

}  // namespace statepack::packager
