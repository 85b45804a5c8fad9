// The Dearchiver's state, shared by the files of its public API: dearchiver.cpp (single unpacks and
// the other objects), unpack_job.cpp (unpack_all and its asynchronous form) and variants.cpp (the
// variants patched unpacks made). One mutex guards it; an unpack job creates pipelines outside it.
#pragma once

#include <condition_variable>
#include <deque>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <set>
#include <string>
#include <string_view>
#include <unordered_map>
#include <vector>

#include "device_limits.hpp"
#include "enabled_features.hpp"
#include "format/archive_format.hpp"
#include "object_cache.hpp"
#include "pipeline_plan.hpp"
#include "statepack/dearchiver.hpp"

namespace statepack {
namespace detail {

// A pipeline an unpack job creates: whoever needs it (the job's own wait, another job, a single unpack
// of the same name and state) waits until it is finished. Guarded by SlotSync::mutex.
struct PipelineSlot {
  bool finished = false;
  bool cancelled = false;  // its job ended before creating it: nothing was made, unpack it again
  const UnpackedPipeline* pipeline = nullptr;
  std::optional<Error> error;
};
// One lock and one condition for every slot of a Dearchiver: shared with its jobs, which may outlive it.
struct SlotSync {
  std::mutex mutex;
  std::condition_variable finished;
};

// Cancels what a job has not begun and waits for its threads (unpack_job.cpp); `dearchiver_gone`: the
// job forgets the Dearchiver, which is being destroyed.
void stop_job(UnpackJob::Shared& job, bool dearchiver_gone = false);
// Waits until every pipeline of the job is finished and its threads have left (unpack_job.cpp).
void wait_for_job(UnpackJob::Shared& job);
bool job_finished(UnpackJob::Shared& job);
// What a patched pipeline's settled state changed of its archived state, as a variant's "state" JSON
// (variants.cpp).
std::string recorded_changes(const format::Pipeline& archived, const PatchableState& settled, bool compute);

}  // namespace detail

struct Dearchiver::State {
  DeviceContext context;
  detail::DeviceCaps caps;  // limits and formats, checked before any vkCreate*
  // Enabled features, every structure; assigned in create(), so the references below stay bound to it.
  detail::EnabledFeatures enabled;
  // Every archive added, and every one a reload brought; an index never changes meaning (the object
  // cache and ArchivedPipeline refer to archives by it). An archive a reload replaced is emptied once
  // nothing made from it is in use (reload.cpp).
  std::vector<Archive> archives;
  // The archives names resolve in, in the order they were added: `archives` indices. A reload replaces
  // one entry.
  std::vector<size_t> active;
  std::vector<size_t> lineage;  // parallel to `archives`: the entry of `active` each one was added as
  detail::ObjectCache cache{context, caps, enabled, archives};  // what pipelines share
  detail::Planner planner{context, caps, enabled.core(), cache};
  bool creation_feedback = false;  // VK_EXT_pipeline_creation_feedback (or Vulkan 1.3) may be chained
  std::deque<UnpackedSignature> signatures;
  std::map<std::pair<size_t, uint32_t>, const UnpackedSignature*> signature_by_layout;
  std::deque<UnpackedPipeline> pipelines;  // stable addresses
  // One per archived pipeline, by archive and then by its place in the archive's (sorted) list: the
  // pipeline made from it without a callback and kept, and the slot of an unpack job creating it so.
  // A name is always taken from the earliest archive that holds it (find, unpack_all), so these are the
  // pipelines by name, reached without hashing one: an unpack job touches one of them per pipeline.
  struct Record {
    const UnpackedPipeline* unmodified = nullptr;
    std::shared_ptr<detail::PipelineSlot> creating;
  };
  std::vector<std::vector<Record>> records;  // parallel to `archives`; an inner list never moves
  Record& record_of(const detail::ArchivedPipeline& p);
  std::map<std::string, const UnpackedPipeline*> variants;  // patched, by variant_key
  struct Place {
    size_t slot;                                                       // in `pipelines`
    std::map<std::string, const UnpackedPipeline*>::iterator variant;  // variants.end(): not a variant
    Record* record;                   // the record whose unmodified pipeline it is, or null
    detail::ArchivedPipeline source;  // what it was made from (a reload compares it with its successor)
    size_t recorded = SIZE_MAX;       // a patched one's entry in `recorded`
  };
  std::unordered_map<const UnpackedPipeline*, Place> place_of;  // live pipelines, for release()
  std::vector<size_t> free_slots;                               // places of released ones
  // Patched pipelines unpack jobs are creating now, by variant key (unpatched ones: Record::creating).
  std::map<std::string, std::shared_ptr<detail::PipelineSlot>> creating_variants;
  std::shared_ptr<detail::SlotSync> sync = std::make_shared<detail::SlotSync>();
  std::vector<std::weak_ptr<UnpackJob::Shared>> jobs;  // stopped before anything here is destroyed
  // Every distinct variant made (variants.cpp writes them): where from, and the state it settled.
  struct Recorded {
    detail::ArchivedPipeline source;
    VkPipelineBindPoint bind_point;
    PatchableState settled;
    bool gone = false;  // its pipeline left the archive in a reload
    std::string key;    // its entry in recorded_keys (empty once a reload changed its state)
  };
  std::vector<Recorded> recorded;
  std::map<std::string, size_t> recorded_keys;  // variant key -> its entry in `recorded`
  // Pipelines a reload replaced, destroyed when the application says the GPU is done with them.
  struct Retired {
    VkPipeline pipeline;
    uint64_t generation;  // the reload that replaced it
  };
  std::vector<Retired> retired;
  uint64_t generation = 0;  // reloads that changed something
  std::mutex mutex;

  // reload.cpp: waits (letting `lock` go meanwhile) until no unpack job is running, then replaces the
  // archive and re-creates what changed.
  void wait_for_jobs(std::unique_lock<std::mutex>& lock);
  Result<ReloadReport> reload(Archive archive, const ReloadOptions& options);

  ~State();

  const format::Contents& contents(size_t archive) const;
  // Names of the given kinds across every archive, for listings and "did you mean".
  std::vector<std::string> names_of(std::initializer_list<ObjectKind> kinds) const;
  std::vector<std::string> pipeline_names() const;
  Result<detail::ArchivedPipeline> find(std::string_view name, format::PipelineKind kind) const;
  // find()'s errors: a pipeline of the other kind, or none of that name (with the nearest names).
  [[gnu::cold]] static Error not_of_kind(std::string_view name, format::PipelineKind actual);
  [[gnu::cold]] Error not_found(std::string_view name) const;

  // Creates the pipeline of a plan, timed, with creation feedback when the device has it; safe to call
  // for different plans on several threads, without the lock.
  Result<void> create(detail::Plan& plan) const;
  // Keeps a created pipeline (in a released one's place when there is one); `key`: its variant key.
  const UnpackedPipeline* keep(detail::Plan& plan, std::string key = {});
  // The variant made before with the same settled state, if any.
  const UnpackedPipeline* earlier_variant(const std::string& key) const;
  Result<void> release(const UnpackedPipeline* pipeline);
  // Cached, being created by a job (waited for, the lock let go meanwhile), or planned, created and
  // kept. `lock` holds `mutex`.
  Result<const UnpackedPipeline*> unpack(std::unique_lock<std::mutex>& lock, std::string_view name,
                                         format::PipelineKind kind, const ModifyCallback& modify);
};

}  // namespace statepack
