// unpack_all and unpack_all_async. Every pipeline of every archive is planned on the calling thread
// (the callbacks run there, under the Dearchiver's lock, and the shared modules and layouts are made
// once), then created on the job's threads without the lock, each kept the moment it exists, so that
// UnpackJob::wait(name) hands out one pipeline while the others are still being created. A failure
// is recorded and stops nothing else.
#include <algorithm>
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <mutex>
#include <thread>
#include <unordered_map>
#include <unordered_set>

#include "api_guard.hpp"

#include "archive_access.hpp"
#include "dearchiver_state.hpp"
#include "support/failure.hpp"
#include "support/suggest.hpp"
#include "variant_key.hpp"

namespace statepack {
using namespace detail;

struct UnpackJob::Shared {
  struct Entry {
    ObjectInfo object;
    ArchivedPipeline source{0, nullptr};  // the archived pipeline it is made from
    std::unique_ptr<Plan> plan;  // this job's plan of it (patched, or to create), until it is created
    std::string key;             // its variant key when patched
    std::shared_ptr<PipelineSlot> slot;
    bool borrowed = false;                    // another job was creating it when this one was planned
    bool settled = false;                     // guarded by sync->mutex: this job is done with it
    std::chrono::nanoseconds created_in{-1};  // set when this job created it
  };

  Dearchiver::State* state = nullptr;  // null once the Dearchiver is gone
  std::shared_ptr<SlotSync> sync;
  std::vector<Entry> entries;
  // Made on the first wait(name) or ready(name): unpack_all never looks a pipeline up by name.
  std::once_flag by_name_made;
  std::unordered_map<std::string_view, size_t> by_name;
  std::vector<UnpackFailure> object_failures;  // signatures, render passes, shaders
  ProgressCallback progress;
  // One progress call at a time, without a lock held while it runs (it may destroy the job, whose
  // stop then wakes the workers waiting for their turn: they skip their calls).
  std::mutex progress_mutex;  // guards reporting, callback_failures
  std::condition_variable progress_turn;
  bool reporting = false;
  std::vector<UnpackFailure> callback_failures;
  std::atomic<size_t> done{0}, next{0};
  std::atomic<bool> cancelled{false};
  size_t settled = 0;  // entries settled; guarded by sync->mutex
  size_t active = 0;   // threads still in work() (a detached one too); guarded by sync->mutex
  std::chrono::steady_clock::time_point start, last_settled;
  std::mutex threads_mutex;  // threads; held through stop_job, so two stops never interleave
  std::vector<std::thread> threads;

  // A thread of the job: work(), then it says it has left, so that wait_all returns only once every
  // thread is done (also one that destroyed the Dearchiver from a progress call and went on alone).
  void thread_body() noexcept {
    work();
    {
      std::lock_guard lock(sync->mutex);
      --active;
    }
    sync->finished.notify_all();
  }

  // Takes the next entry until none is left (or the job is cancelled): a worker's whole life. Nothing
  // may escape a thread: whatever an entry throws settles it as failed.
  void work() noexcept {
    for (;;) {
      if (cancelled) return;
      const size_t i = next++;
      if (i >= entries.size()) return;
      try {
        run(entries[i]);
      } catch (...) {
        settle_failed(entries[i]);
      }
    }
  }

  void run(Entry& e) {
    if (!e.borrowed && e.plan) {
      create(e);
    } else {
      std::unique_lock lock(sync->mutex);
      if (e.settled) return;  // settled at planning, and reported there
      // Another job creates it: its outcome is this job's too, unless that job ended first.
      sync->finished.wait(lock, [&] { return e.slot->finished || cancelled; });
      if (!e.slot->finished) return;
      if (e.slot->cancelled) {
        lock.unlock();
        make_instead(e);
        lock.lock();
      }
      settle_locked(e);
    }
    sync->finished.notify_all();
    report(e);
  }

  void create(Entry& e) {
    Plan& plan = *e.plan;
    std::optional<Error> error;
    if (auto created = state->create(plan); !created) error = created.error();
    const UnpackedPipeline* kept = nullptr;
    {
      std::lock_guard lock(state->mutex);
      forget_locked(e);
      if (!error) {
        e.created_in = plan.out.creation.time;
        const VkPipeline made = plan.out.pipeline;
        try {
          kept = state->keep(plan, e.key);
        } catch (...) {  // no memory to keep it: it is nobody's, so it goes now
          state->caps.vk.vkDestroyPipeline(state->context.device, made, state->context.allocator);
          throw;
        }
      }
    }
    e.plan.reset();
    std::lock_guard lock(sync->mutex);
    e.slot->pipeline = kept;
    e.slot->error = std::move(error);
    e.slot->finished = true;
    settle_locked(e);
  }

  // A pipeline another job was to create, but that job ended before it did: this one makes it, as a
  // single unpack would (the lock held: it is rare), into a slot of its own.
  void make_instead(Entry& e) {
    auto own = std::make_shared<PipelineSlot>();
    std::unique_lock lock(state->mutex);
    Result<const UnpackedPipeline*> made = detail::failure(ErrorCode::cancelled, "");
    if (!e.plan) {  // unpatched: planned without a callback, so the single-object path does it all
      const bool existed = state->record_of(e.source).unmodified != nullptr;
      made = state->unpack(lock, e.object.name,
                           e.object.kind == ObjectKind::compute_pipeline ? format::PipelineKind::compute
                                                                         : format::PipelineKind::graphics,
                           {});
      if (made && !existed) e.created_in = (*made)->creation.time;
    } else if (const UnpackedPipeline* earlier = state->earlier_variant(e.key)) {
      made = earlier;
    } else if (auto created = state->create(*e.plan); created) {
      e.created_in = e.plan->out.creation.time;
      made = state->keep(*e.plan, e.key);
    } else {
      made = created.error();
    }
    e.plan.reset();
    lock.unlock();
    own->finished = true;
    if (made)
      own->pipeline = *made;
    else
      own->error = made.error();
    std::lock_guard slots(sync->mutex);
    e.slot = std::move(own);
  }

  // An entry whose work threw (out of memory): failed, with an error that needs no allocation of its own
  // beyond what a short string does not.
  void settle_failed(Entry& e) noexcept {
    try {
      if (state) {
        std::lock_guard lock(state->mutex);
        forget_locked(e);
      }
      std::lock_guard lock(sync->mutex);
      if (e.settled) return;
      if (!e.slot->finished) {
        e.slot->error = detail::failure(ErrorCode::out_of_memory, "out of memory");
        e.slot->finished = true;
      }
      settle_locked(e);
    } catch (...) {  // nothing more can be done; waiters are woken below
    }
    sync->finished.notify_all();
  }

  // Removes the entry from the Dearchiver's pipelines being created (state->mutex held).
  void forget_locked(const Entry& e) {
    if (e.borrowed) return;
    if (e.key.empty()) {
      if (!e.source.pipeline) return;  // nothing was planned (out of memory before)
      auto& record = state->record_of(e.source);
      if (record.creating == e.slot) record.creating.reset();
    } else {
      auto it = state->creating_variants.find(e.key);
      if (it != state->creating_variants.end() && it->second == e.slot) state->creating_variants.erase(it);
    }
  }

  void settle_locked(Entry& e) {  // sync->mutex held
    e.settled = true;
    ++settled;
    last_settled = std::chrono::steady_clock::now();
  }

  void report(const Entry& e) {
    if (!progress) {
      ++done;
      return;
    }
    size_t count = 0;
    {
      std::unique_lock lock(progress_mutex);
      progress_turn.wait(lock, [&] { return !reporting || cancelled; });
      count = ++done;
      if (reporting) return;  // cancelled while another call runs: the job is ending, nobody is told
      reporting = true;
    }
    const UnpackProgress p{&e.object, e.slot->pipeline, e.slot->error ? &*e.slot->error : nullptr, count,
                           entries.size()};
    std::optional<std::string> thrown;
    try {
      progress(p);
    } catch (const std::exception& x) {
      thrown = x.what();
    } catch (...) {
      thrown = "";
    }
    std::lock_guard lock(progress_mutex);
    if (thrown)
      callback_failures.push_back(
          {e.object, detail::failure(ErrorCode::invalid_argument,
                                     "the progress callback threw while told of pipeline '" + e.object.name +
                                         "'" + (thrown->empty() ? "" : ": ") + *thrown)});
    reporting = false;
    progress_turn.notify_all();
  }

  Entry* entry(std::string_view name) {
    std::call_once(by_name_made, [this] {
      by_name.reserve(entries.size());
      for (size_t i = 0; i < entries.size(); ++i) by_name.emplace(entries[i].object.name, i);
    });
    auto it = by_name.find(name);
    return it == by_name.end() ? nullptr : &entries[it->second];
  }

  // A pipeline nobody made, or (once the Dearchiver is gone) one destroyed with it.
  Error cancelled_error(const std::string& name) const {  // sync->mutex held
    return detail::failure(
        ErrorCode::cancelled,
        "pipeline '" + name + "': " +
            (state ? "the unpack job was destroyed before it created the pipeline"
                   : "the Dearchiver was destroyed (with every pipeline it made) while its unpack job ran"));
  }
};

namespace detail {

void stop_job(UnpackJob::Shared& job, bool dearchiver_gone) {
  std::lock_guard threads_lock(job.threads_mutex);
  job.cancelled = true;
  { std::lock_guard lock(job.sync->mutex); }  // a worker waiting on another job's pipeline sees it
  job.sync->finished.notify_all();
  { std::lock_guard lock(job.progress_mutex); }  // and one waiting for its turn to report
  job.progress_turn.notify_all();
  for (auto& t : job.threads) {
    if (t.get_id() == std::this_thread::get_id())
      t.detach();  // destroyed from its own progress callback: it returns from work() next
    else if (t.joinable())
      t.join();
  }
  job.threads.clear();
  // What the threads did not begin is made by nobody: whoever waits for it makes it itself.
  std::unique_lock state_lock =
      job.state ? std::unique_lock(job.state->mutex) : std::unique_lock<std::mutex>();
  std::lock_guard lock(job.sync->mutex);
  for (auto& e : job.entries) {
    if (e.settled) continue;
    if (!e.borrowed && e.plan) {
      if (job.state) job.forget_locked(e);
      e.slot->cancelled = e.slot->finished = true;
    }
    e.plan.reset();
    job.settle_locked(e);
  }
  if (dearchiver_gone) job.state = nullptr;
  job.sync->finished.notify_all();
}

bool job_finished(UnpackJob::Shared& job) {
  std::lock_guard lock(job.sync->mutex);
  return job.settled == job.entries.size() && job.active == 0;
}

void wait_for_job(UnpackJob::Shared& job) {
  std::unique_lock lock(job.sync->mutex);
  job.sync->finished.wait(lock, [&] { return job.settled == job.entries.size() && job.active == 0; });
}

}  // namespace detail

namespace {

// Plans one pipeline into `e` (state.mutex held): settled at once when made before or refused, borrowed
// when another job is creating it, else this job's to create (registered as being created).
void plan_entry(UnpackJob::Shared& job, Dearchiver::State& state, const UnpackAllOptions& options,
                const ArchivedPipeline& found, UnpackJob::Shared::Entry& e) {
  const format::Pipeline& p = *found.pipeline;
  const bool compute = p.kind == format::PipelineKind::compute;
  e.object = {p.name, compute ? ObjectKind::compute_pipeline : ObjectKind::graphics_pipeline};
  e.source = found;
  auto settle = [&](const UnpackedPipeline* made, std::optional<Error> error) {
    e.slot = std::make_shared<PipelineSlot>();
    e.slot->finished = true;
    e.slot->pipeline = made;
    e.slot->error = std::move(error);
    e.settled = true;
    ++job.settled;
  };
  Dearchiver::State::Record& record = state.record_of(found);
  if (!options.patch) {  // a patch callback sees every pipeline, so nothing made before is reused then
    if (record.unmodified) return settle(record.unmodified, {});
    if (record.creating) {
      e.slot = record.creating;  // another job's
      e.borrowed = true;
      return;
    }
  }
  // The single-object path's callback, told which pipeline it patches: the patched state goes through
  // the same checks as unpack_graphics/unpack_compute with a modify callback.
  ModifyCallback modify;
  if (options.patch) modify = [&options, &e](PatchableState& s) { options.patch(e.object, s); };
  auto plan =
      compute ? state.planner.plan_compute(found, modify) : state.planner.plan_graphics(found, modify);
  if (!plan) return settle(nullptr, plan.error());
  if (options.patch) {
    e.key = variant_key(p.name, **plan);
    if (const UnpackedPipeline* earlier = state.earlier_variant(e.key)) return settle(earlier, {});
    if (auto it = state.creating_variants.find(e.key); it != state.creating_variants.end()) {
      e.slot = it->second;  // another job's; the plan is kept in case that job ends first
      e.borrowed = true;
      e.plan = std::move(plan.value());
      return;
    }
  }
  e.plan = std::move(plan.value());
  e.slot = std::make_shared<PipelineSlot>();
  (e.key.empty() ? record.creating : state.creating_variants[e.key]) = e.slot;
}

// Plans every pipeline not yet made (the callbacks run here), makes the other objects, and starts
// `threads` workers; the job's entries are in archive order, the earliest archive winning a name. If
// anything throws (no memory, a callback's bad_alloc), the job is stopped first, so that nothing is left
// registered as being created.
std::shared_ptr<UnpackJob::Shared> start_job(Dearchiver& dearchiver, Dearchiver::State& state,
                                             const UnpackAllOptions& options, size_t threads) {
  auto job = std::make_shared<UnpackJob::Shared>();
  job->sync = state.sync;
  job->progress = options.progress;
  job->start = job->last_settled = std::chrono::steady_clock::now();
  job->state = &state;
  std::vector<ObjectInfo> others;
  {
    std::lock_guard lock(state.mutex);
    try {
      // Names are unique within an archive (checked at load), so only a second archive needs `seen`;
      // the names it holds live in the archives, as long as the job's state.
      std::unordered_set<std::string_view> seen;
      const bool several = state.active.size() > 1;
      size_t total = 0;
      for (size_t a : state.active) total += state.contents(a).pipelines.size();
      job->entries.reserve(total);
      // Room for every pipeline the job may keep, so that keeping them never rehashes.
      state.place_of.reserve(state.place_of.size() + total);
      for (size_t a : state.active)
        for (const auto& p : state.contents(a).pipelines)
          if (!several || seen.insert(p.name).second)  // the earliest archive wins
            plan_entry(*job, state, options, ArchivedPipeline{a, &p}, job->entries.emplace_back());
      std::erase_if(state.jobs, [](const auto& weak) { return weak.expired(); });
      state.jobs.push_back(job);
      for (size_t a : state.active) detail::append_other_objects(state.contents(a), others);
    } catch (...) {
      for (auto& e : job->entries) job->forget_locked(e);
      for (auto& e : job->entries)
        if (e.slot && !e.borrowed && !e.settled) e.slot->cancelled = e.slot->finished = true;
      throw;
    }
  }
  try {
    // The other named objects, so that everything is ready; each is quick to make.
    for (const auto& object : others) {
      std::optional<Error> failed;
      if (object.kind == ObjectKind::resource_signature) {
        if (auto r = dearchiver.unpack_signature(object.name); !r) failed = r.error();
      } else if (object.kind == ObjectKind::render_pass) {
        if (auto r = dearchiver.unpack_render_pass(object.name); !r) failed = r.error();
      } else if (auto r = dearchiver.unpack_shader(object.name); !r) {
        failed = r.error();
      }
      if (failed) job->object_failures.push_back({object, std::move(*failed)});
    }
    std::vector<size_t> settled_at_planning;  // read before any thread settles more
    for (size_t i = 0; i < job->entries.size(); ++i)
      if (job->entries[i].settled) settled_at_planning.push_back(i);
    const size_t to_make = job->entries.size() - settled_at_planning.size();  // no more threads than these
    bool started = false;
    {
      std::lock_guard lock(job->threads_mutex);
      job->threads.reserve(std::min(threads, to_make));
      try {
        for (size_t i = 0; i < threads && i < to_make; ++i) {
          {
            std::lock_guard count(job->sync->mutex);
            ++job->active;
          }
          try {
            job->threads.emplace_back([job] { job->thread_body(); });
          } catch (...) {
            std::lock_guard count(job->sync->mutex);
            --job->active;
            throw;
          }
        }
      } catch (const std::system_error&) {  // no more threads: those started do the work
      }
      started = !job->threads.empty() || threads == 0;
    }
    if (!started) job->work();  // not one thread: this one does it all
    for (size_t i : settled_at_planning) job->report(job->entries[i]);
  } catch (...) {
    stop_job(*job);
    throw;
  }
  return job;
}

size_t thread_count(uint32_t threads) {
  return threads ? threads : std::max(1u, std::thread::hardware_concurrency());
}

UnpackReport report_of(UnpackJob::Shared& job) {
  UnpackReport report;
  std::lock_guard lock(job.sync->mutex);  // a slot of another job may be finishing
  for (const auto& e : job.entries) {
    const PipelineSlot& slot = *e.slot;
    if (!slot.finished || slot.cancelled || !job.state)
      report.failures.push_back({e.object, job.cancelled_error(e.object.name)});
    else if (slot.pipeline)
      report.pipelines.push_back(slot.pipeline);
    else
      report.failures.push_back({e.object, *slot.error});
    if (e.created_in.count() >= 0) report.creation_time += e.created_in;
  }
  report.failures.insert(report.failures.end(), job.object_failures.begin(), job.object_failures.end());
  report.failures.insert(report.failures.end(), job.callback_failures.begin(), job.callback_failures.end());
  report.wall_time = job.last_settled - job.start;
  return report;
}

// unpack_all's single error: the one failure itself, or every failure in one message.
Error combined_error(const std::vector<UnpackFailure>& failures) {
  if (failures.size() == 1) return failures.front().error;
  constexpr size_t kListed = 20;  // a message stays readable; UnpackReport has them all
  std::string message = std::to_string(failures.size()) + " objects failed: ";
  for (size_t i = 0; i < failures.size() && i < kListed; ++i)
    message += (i ? "; " : "") + failures[i].error.message;
  if (failures.size() > kListed)
    message +=
        "; and " + std::to_string(failures.size() - kListed) + " more (unpack_all(options) lists each)";
  Error first = failures.front().error;
  return detail::failure(first.code, std::move(message), first.vk_result);
}

}  // namespace

UnpackJob::UnpackJob(std::shared_ptr<Shared> shared) : shared_(std::move(shared)) {}
UnpackJob::UnpackJob(UnpackJob&&) noexcept = default;
UnpackJob& UnpackJob::operator=(UnpackJob&& other) noexcept {
  if (this != &other) {
    if (shared_) stop_job(*shared_);
    shared_ = std::move(other.shared_);
  }
  return *this;
}
UnpackJob::~UnpackJob() {
  if (shared_) stop_job(*shared_);
}

Result<const UnpackedPipeline*> UnpackJob::wait(std::string_view name) {
  return api_guard("UnpackJob::wait", [&]() -> Result<const UnpackedPipeline*> {
    Shared::Entry* e = shared_ ? shared_->entry(name) : nullptr;
    if (!e) {
      std::vector<std::string> names;
      if (shared_)
        for (const auto& entry : shared_->entries) names.push_back(entry.object.name);
      return detail::failure(ErrorCode::not_found, "the unpack job creates no pipeline named '" +
                                                       std::string(name) + "'" + did_you_mean(name, names));
    }
    std::unique_lock lock(shared_->sync->mutex);
    shared_->sync->finished.wait(lock, [&] { return e->slot->finished || e->settled; });
    if (!e->slot->finished || e->slot->cancelled || !shared_->state)
      return shared_->cancelled_error(e->object.name);
    if (e->slot->error) return *e->slot->error;
    return e->slot->pipeline;
  });
}

bool UnpackJob::ready(std::string_view name) const {
  Shared::Entry* e = shared_ ? shared_->entry(name) : nullptr;
  if (!e) return false;
  std::lock_guard lock(shared_->sync->mutex);
  return e->slot->finished;
}

size_t UnpackJob::done() const {
  return shared_ ? shared_->done.load() : 0;
}

size_t UnpackJob::total() const {
  return shared_ ? shared_->entries.size() : 0;
}

UnpackReport UnpackJob::wait_all() {
  if (!shared_) return {};
  {
    std::unique_lock lock(shared_->sync->mutex);
    shared_->sync->finished.wait(
        lock, [&] { return shared_->settled == shared_->entries.size() && shared_->active == 0; });
  }
  // The last progress calls end with their threads. Joined outside the lock, which stop_job takes (the
  // Dearchiver may be destroyed from a progress call meanwhile).
  std::vector<std::thread> threads;
  {
    std::lock_guard lock(shared_->threads_mutex);
    threads.swap(shared_->threads);
  }
  for (auto& t : threads) {
    if (t.get_id() == std::this_thread::get_id())
      t.detach();
    else if (t.joinable())
      t.join();
  }
  return report_of(*shared_);
}

Result<UnpackJob> Dearchiver::unpack_all_async(UnpackAllOptions options) {
  return api_guard("Dearchiver::unpack_all_async", [&]() -> Result<UnpackJob> {
    return UnpackJob(start_job(*this, *state_, options, thread_count(options.threads)));
  });
}

Result<UnpackReport> Dearchiver::unpack_all(const UnpackAllOptions& options) {
  return api_guard("Dearchiver::unpack_all", [&]() -> Result<UnpackReport> {
    // The calling thread is one of the workers.
    UnpackJob job(start_job(*this, *state_, options, thread_count(options.threads) - 1));
    job.shared_->work();
    return job.wait_all();
  });
}

Result<std::vector<const UnpackedPipeline*>> Dearchiver::unpack_all(uint32_t threads) {
  return unpack_all(PatchCallback{}, threads);
}

Result<std::vector<const UnpackedPipeline*>> Dearchiver::unpack_all(const PatchCallback& patch,
                                                                    uint32_t threads) {
  UnpackAllOptions options;
  options.patch = patch;
  options.threads = threads;
  auto report = unpack_all(options);
  if (!report) return report.error();
  if (!report->failures.empty()) return combined_error(report->failures);
  return std::move(report->pipelines);
}

}  // namespace statepack
