// unpack_all reporting every failure with progress, and its non-blocking form: UnpackJob::wait(name)
// hands out one pipeline while the job's threads still create the others. "While" is proven with an
// allocator that holds the job's thread inside the driver (a gate), not with sleeps.
#include <condition_variable>
#include <cstdlib>
#include <map>
#include <mutex>
#include <optional>
#include <thread>
#include <unordered_map>

#include "common/vulkan_test_fixture.hpp"

namespace statepack::testing {
namespace {

// VkAllocationCallbacks whose allocations, once the gate is closed, wait on every thread but the one
// that made it (the test's) until it opens: the job's thread stops inside vkCreate*Pipelines.
class GateAllocator {
 public:
  VkAllocationCallbacks callbacks() {
    VkAllocationCallbacks c{};
    c.pUserData = this;
    c.pfnAllocation = [](void* self, size_t size, size_t alignment, VkSystemAllocationScope) {
      return static_cast<GateAllocator*>(self)->allocate(size, alignment);
    };
    c.pfnReallocation = [](void* self, void* original, size_t size, size_t alignment,
                           VkSystemAllocationScope) {
      return static_cast<GateAllocator*>(self)->reallocate(original, size, alignment);
    };
    c.pfnFree = [](void* self, void* memory) { static_cast<GateAllocator*>(self)->release(memory); };
    return c;
  }
  void close() {
    std::lock_guard lock(mutex_);
    closed_ = true;
  }
  void open() {
    {
      std::lock_guard lock(mutex_);
      closed_ = false;
    }
    changed_.notify_all();
  }
  // Waits until another thread is held at the gate; false after a minute (the driver never allocated).
  bool wait_until_held() {
    std::unique_lock lock(mutex_);
    return changed_.wait_for(lock, std::chrono::minutes(1), [&] { return held_ > 0; });
  }

 private:
  void* allocate(size_t size, size_t alignment) {
    std::unique_lock lock(mutex_);
    if (std::this_thread::get_id() != owner_) {
      ++held_;
      changed_.notify_all();
      changed_.wait(lock, [&] { return !closed_; });
      --held_;
    }
    void* memory = nullptr;
    if (posix_memalign(&memory, std::max(alignment, sizeof(void*)), std::max<size_t>(size, 1)) != 0)
      return nullptr;
    sizes_[memory] = size;
    return memory;
  }
  void* reallocate(void* original, size_t size, size_t alignment) {
    if (!original) return allocate(size, alignment);
    if (size == 0) {
      release(original);
      return nullptr;
    }
    void* memory = allocate(size, alignment);
    if (!memory) return nullptr;
    size_t old_size = 0;
    {
      std::lock_guard lock(mutex_);
      old_size = sizes_.at(original);
    }
    std::memcpy(memory, original, std::min(old_size, size));
    release(original);
    return memory;
  }
  void release(void* memory) {
    if (!memory) return;
    {
      std::lock_guard lock(mutex_);
      sizes_.erase(memory);
    }
    std::free(memory);
  }

  std::mutex mutex_;
  std::condition_variable changed_;
  bool closed_ = false;
  size_t held_ = 0;
  const std::thread::id owner_ = std::this_thread::get_id();
  std::unordered_map<void*, size_t> sizes_;
};

class UnpackJobTest : public VulkanTest {
 protected:
  // A device of its own whose allocator is the gate: lavapipe allocates a pipeline through the device's
  // callbacks, so a closed gate holds a pipeline's creation inside the driver.
  static Result<std::unique_ptr<bootstrap::VulkanContext>> gated_device(const VkAllocationCallbacks& gate) {
    bootstrap::VulkanContextOptions options;
    options.require_lavapipe = true;
    options.enable_supported_features = true;
    options.device_allocator = &gate;
    return bootstrap::VulkanContext::create(options);
  }

  Dearchiver dearchiver_with(const char* archive_path) {
    auto dearchiver = Dearchiver::create(vk_->device_context());
    EXPECT_TRUE(dearchiver) << dearchiver.error().message;
    auto archive = Archive::from_file(archive_path);
    EXPECT_TRUE(archive) << archive.error().message;
    EXPECT_TRUE(dearchiver->add_archive(std::move(*archive)));
    return std::move(dearchiver.value());
  }
};

TEST_F(UnpackJobTest, TheFirstPipelineIsHandedOutWhileTheLastIsStillBeingCreated) {
  GateAllocator gate;
  const VkAllocationCallbacks callbacks = gate.callbacks();
  auto device = gated_device(callbacks);
  ASSERT_TRUE(device) << device.error().message;
  auto created = Dearchiver::create((*device)->device_context());
  ASSERT_TRUE(created) << created.error().message;
  Dearchiver& dearchiver = *created;
  ASSERT_TRUE(dearchiver.add_archive(Archive::from_file(STATEPACK_TEST_ARCHIVE).value()));
  std::vector<std::string> reported;
  UnpackAllOptions options;
  options.threads = 1;  // one creating thread: archive order, "Fill Buffer PSO" then "Gradient PSO"
  options.progress = [&](const UnpackProgress& p) {
    reported.push_back(p.object->name + (p.error ? ": failed" : ": created"));
    EXPECT_EQ(p.total, 2u);
    if (p.done == 1) gate.close();  // the next pipeline's creation waits in the driver's first allocation
  };
  auto job = dearchiver.unpack_all_async(options);
  ASSERT_TRUE(job) << job.error().message;
  EXPECT_EQ(job->total(), 2u);

  auto first = job->wait("Fill Buffer PSO");
  ASSERT_TRUE(first) << first.error().message;
  EXPECT_NE((*first)->pipeline, VK_NULL_HANDLE);
  EXPECT_EQ((*first)->bind_point, VK_PIPELINE_BIND_POINT_COMPUTE);
  ASSERT_TRUE(gate.wait_until_held())
      << "the second pipeline's creation never allocated through the callbacks";
  // The job's thread is inside vkCreateGraphicsPipelines for the last pipeline: not finished yet.
  EXPECT_FALSE(job->ready("Gradient PSO"));
  EXPECT_TRUE(job->ready("Fill Buffer PSO"));
  EXPECT_EQ(job->done(), 1u);
  EXPECT_EQ(reported, std::vector<std::string>{"Fill Buffer PSO: created"});

  // A single unpack of the pipeline the job is making waits for that one rather than making another.
  Result<const UnpackedPipeline*> single = Error{ErrorCode::not_found, "not run"};
  std::thread other([&] { single = dearchiver.unpack_graphics("Gradient PSO"); });
  gate.open();
  other.join();
  auto last = job->wait("Gradient PSO");
  ASSERT_TRUE(last) << last.error().message;
  ASSERT_TRUE(single) << single.error().message;
  EXPECT_EQ(*single, *last);
  UnpackReport report = job->wait_all();
  EXPECT_TRUE(report.ok());
  ASSERT_EQ(report.pipelines.size(), 2u);
  EXPECT_EQ(report.pipelines[0], *first);
  EXPECT_EQ(report.pipelines[1], *last);
  EXPECT_EQ(reported, (std::vector<std::string>{"Fill Buffer PSO: created", "Gradient PSO: created"}));
  EXPECT_GE(report.wall_time, report.creation_time / 2);  // one thread: the creations happened within it
  auto unknown = job->wait("Gradient PS0");
  ASSERT_FALSE(unknown);
  EXPECT_EQ(unknown.error().code, ErrorCode::not_found);
  EXPECT_NE(unknown.error().message.find("did you mean 'Gradient PSO'"), std::string::npos)
      << unknown.error().message;
  dearchiver = Dearchiver::create((*device)->device_context()).value();  // the first one destroyed
  (*device)->destroy_device();  // the layer reports what was left alive
  for (const auto& message : (*device)->validation_messages()) ADD_FAILURE() << message;
}

// Two jobs need the same pipelines: the second waits for the first's. When the first ends before making
// them (destroyed from its own progress callback, deterministically after its second pipeline), the
// second makes them itself instead of failing them as cancelled.
TEST_F(UnpackJobTest, AJobMakesWhatAnEndedJobLeftUnmade) {
  GateAllocator gate;
  const VkAllocationCallbacks callbacks = gate.callbacks();
  auto device = gated_device(callbacks);
  ASSERT_TRUE(device) << device.error().message;
  {
    auto dearchiver = Dearchiver::create((*device)->device_context());
    ASSERT_TRUE(dearchiver) << dearchiver.error().message;
    // Four pipelines in this order: Fill Buffer PSO, Gradient PSO, Negated, Seven.
    for (const char* path : {STATEPACK_TEST_ARCHIVE, STATEPACK_SPECIALIZATION_ARCHIVE})
      ASSERT_TRUE(dearchiver->add_archive(Archive::from_file(path).value()));
    std::optional<UnpackJob> first;
    UnpackAllOptions options;
    options.threads = 1;
    options.progress = [&](const UnpackProgress& p) {
      if (p.done == 1) gate.close();   // the second pipeline waits in the driver
      if (p.done == 2) first.reset();  // ends the job: the last two are never begun by it
    };
    auto started = dearchiver->unpack_all_async(options);
    ASSERT_TRUE(started) << started.error().message;
    first.emplace(std::move(*started));
    ASSERT_TRUE(first->wait("Fill Buffer PSO"));
    ASSERT_TRUE(gate.wait_until_held());
    // The second job plans while the first still holds the last three as being made.
    UnpackAllOptions plain;
    plain.threads = 1;
    auto second = dearchiver->unpack_all_async(plain);
    ASSERT_TRUE(second) << second.error().message;
    gate.open();
    UnpackReport report = second->wait_all();
    for (const auto& f : report.failures) ADD_FAILURE() << f.error.message;
    ASSERT_EQ(report.pipelines.size(), 4u);
    for (const UnpackedPipeline* p : report.pipelines) EXPECT_NE(p->pipeline, VK_NULL_HANDLE) << p->name;
    EXPECT_GT(report.creation_time.count(), 0);  // it made Negated and Seven itself
  }
  (*device)->destroy_device();
  for (const auto& message : (*device)->validation_messages()) ADD_FAILURE() << message;
}

// A progress callback may destroy the Dearchiver (on two threads, the other worker waits for its turn to
// report): the job ends without a deadlock and the Dearchiver's pipelines go with it.
TEST_F(UnpackJobTest, TheDearchiverMayBeDestroyedFromAProgressCallback) {
  std::optional<Dearchiver> dearchiver = Dearchiver::create(vk_->device_context()).value();
  for (const auto& path : corpus_archives_without_run_time_state())
    ASSERT_TRUE(dearchiver->add_archive(Archive::from_file(path).value()));
  UnpackAllOptions options;
  options.threads = 2;
  size_t calls = 0;
  options.progress = [&](const UnpackProgress&) {
    if (++calls == 2) dearchiver.reset();
  };
  auto job = dearchiver->unpack_all_async(options);
  ASSERT_TRUE(job) << job.error().message;
  const size_t total = job->total();
  UnpackReport report = job->wait_all();
  EXPECT_FALSE(dearchiver);
  EXPECT_EQ(report.failures.size(), total);
  for (const auto& f : report.failures) EXPECT_EQ(f.error.code, ErrorCode::cancelled) << f.error.message;
}

// Every failure is reported (none stops the others), each pipeline is told to the progress callback
// once, in order, and the old unpack_all signature names every failure in one error.
TEST_F(UnpackJobTest, EveryFailureIsReportedAndProgressCountsEachPipelineOnce) {
  Dearchiver dearchiver = dearchiver_with(STATEPACK_RUN_TIME_FORMATS_ARCHIVE);
  std::map<std::string, std::string> outcome;
  std::vector<size_t> done;
  UnpackAllOptions options;
  options.threads = 2;
  options.progress = [&](const UnpackProgress& p) {
    EXPECT_TRUE(outcome.emplace(p.object->name, p.error ? p.error->message : "created").second)
        << p.object->name;
    EXPECT_EQ(p.pipeline == nullptr, p.error != nullptr);
    EXPECT_EQ(p.total, 4u);
    done.push_back(p.done);
  };
  auto report = dearchiver.unpack_all(options);
  ASSERT_TRUE(report) << report.error().message;
  EXPECT_EQ(done, (std::vector<size_t>{1, 2, 3, 4}));
  ASSERT_EQ(report->failures.size(), 2u);  // the two pipelines whose render target is left to run time
  EXPECT_EQ(report->failures[0].object.name, "Overlay Gradient PSO");
  EXPECT_EQ(report->failures[1].object.name, "Swapchain Gradient PSO");
  for (const UnpackFailure& f : report->failures) {
    EXPECT_EQ(f.object.kind, ObjectKind::graphics_pipeline);
    EXPECT_EQ(f.error.code, ErrorCode::invalid_argument);
    EXPECT_EQ(f.error.message, "pipeline '" + f.object.name +
                                   "': render target 0 is UNKNOWN (a format set at run time); set "
                                   "PatchableState::color_formats[0] in the modify callback, or give "
                                   "RTVFormats[0] in the notation and "
                                   "pack again");
    EXPECT_EQ(outcome.at(f.object.name), f.error.message);
  }
  ASSERT_EQ(report->pipelines.size(), 2u);
  EXPECT_EQ(report->pipelines[0]->name, "Fill Buffer PSO");
  EXPECT_EQ(report->pipelines[1]->name, "Offscreen Gradient PSO");
  for (const UnpackedPipeline* p : report->pipelines) {
    EXPECT_EQ(outcome.at(p->name), "created");
    EXPECT_GT(p->creation.time.count(), 0) << p->name;
  }
  EXPECT_GT(report->creation_time.count(), 0);
  // A progress callback that throws is reported, and the job goes on.
  options.progress = [](const UnpackProgress& p) {
    if (p.object->name == "Fill Buffer PSO") throw std::runtime_error("no loading screen");
  };
  auto thrown = dearchiver.unpack_all(options);
  ASSERT_TRUE(thrown);
  ASSERT_EQ(thrown->failures.size(), 3u);
  EXPECT_EQ(thrown->failures[2].error.message,
            "the progress callback threw while told of pipeline 'Fill Buffer PSO': no loading screen");
}

// Pipelines say how long the driver took (VK_EXT_pipeline_creation_feedback is core in Vulkan 1.3,
// which lavapipe has), beside statepack's own clock around the call.
TEST_F(UnpackJobTest, PipelinesCarryTheirCreationTimeAndTheDriversFeedback) {
  Dearchiver dearchiver = dearchiver_with(STATEPACK_TEST_ARCHIVE);
  auto pso = dearchiver.unpack_graphics("Gradient PSO");
  ASSERT_TRUE(pso) << pso.error().message;
  const PipelineCreation& c = (*pso)->creation;
  EXPECT_GT(c.time.count(), 0);
  ASSERT_TRUE(c.feedback);
  EXPECT_GT(c.driver_time.count(), 0);
  EXPECT_LE(c.driver_time, c.time);  // the driver's part of the call
  EXPECT_FALSE(c.cache_hit);         // no pipeline cache was given
}

// Destroying the Dearchiver while a job creates pipelines stops the job: what it had not begun is
// cancelled, what it made is destroyed with the Dearchiver (the validation layer, which reports leaked
// objects at device teardown, stays silent), and the job's handle still answers.
TEST_F(UnpackJobTest, DestroyingTheDearchiverMidJobCancelsTheRestAndLeaksNothing) {
  std::optional<UnpackJob> job;
  size_t total = 0;
  {
    auto dearchiver = Dearchiver::create(vk_->device_context());
    ASSERT_TRUE(dearchiver);
    for (const auto& path : corpus_archives_without_run_time_state())
      ASSERT_TRUE(dearchiver->add_archive(Archive::from_file(path).value()));
    UnpackAllOptions options;
    options.threads = 1;
    auto started = dearchiver->unpack_all_async(options);
    ASSERT_TRUE(started) << started.error().message;
    total = started->total();
    ASSERT_GE(total, 6u);
    job.emplace(std::move(*started));
  }
  UnpackReport report = job->wait_all();
  EXPECT_TRUE(report.pipelines.empty());  // they went with the Dearchiver
  EXPECT_EQ(report.failures.size(), total);
  for (const UnpackFailure& f : report.failures) {
    EXPECT_EQ(f.error.code, ErrorCode::cancelled) << f.error.message;
    auto waited = job->wait(f.object.name);
    ASSERT_FALSE(waited);
    EXPECT_EQ(waited.error().code, ErrorCode::cancelled);
  }
  job.reset();
  EXPECT_TRUE(vk_->validation_messages().empty()) << vk_->validation_messages().front();
}

}  // namespace
}  // namespace statepack::testing
