// ThreadSanitizer run of the dearchiver: several archives added, unpack_all on worker threads while
// other threads unpack single objects through the same Dearchiver. Built by tests/CMakeLists.txt as
// dearchiver_tsan_tests, which compiles the dearchiver's sources with -fsanitize=thread; the Vulkan
// loader, the validation layer and lavapipe are not instrumented (see tests/tsan.supp).
#include <algorithm>
#include <atomic>
#include <optional>
#include <set>
#include <thread>

#include "common/vulkan_test_fixture.hpp"
#include "format/archive_format.hpp"
#include "runtime/archive_access.hpp"

namespace statepack::testing {
namespace {

class TsanUnpack : public VulkanTest {};

TEST_F(TsanUnpack, ConcurrentUnpackAllAndSingleUnpacksAgree) {
  auto dearchiver = Dearchiver::create(vk_->device_context());
  ASSERT_TRUE(dearchiver);
  std::vector<std::pair<std::string, format::PipelineKind>> pipelines;
  std::vector<std::string> signatures;
  std::set<std::string> names;
  for (const auto& path : corpus_archives_without_run_time_state()) {
    auto archive = Archive::from_file(path);
    ASSERT_TRUE(archive) << archive.error().message;
    for (const auto& p : detail::ArchiveAccess::contents(*archive).pipelines)
      if (names.insert(p.name).second) pipelines.emplace_back(p.name, p.kind);
    for (const auto& l : detail::ArchiveAccess::contents(*archive).set_layouts)
      if (!l.name.empty()) signatures.push_back(l.name);
    ASSERT_TRUE(dearchiver->add_archive(std::move(*archive)));
  }
  ASSERT_GE(pipelines.size(), 6u);

  std::vector<std::vector<const UnpackedPipeline*>> all(2);
  std::vector<std::string> errors(4);
  std::vector<std::thread> threads;
  for (size_t t = 0; t < 2; ++t)
    threads.emplace_back([&, t] {
      auto result = dearchiver->unpack_all(3);  // itself creates pipelines on three threads
      if (result)
        all[t] = *result;
      else
        errors[t] = result.error().message;
    });
  for (size_t t = 2; t < 4; ++t)
    threads.emplace_back([&, t] {
      // Opposite orders, so that the two threads meet on every object.
      for (size_t i = 0; i < pipelines.size(); ++i) {
        const auto& [name, kind] = pipelines[t == 2 ? i : pipelines.size() - 1 - i];
        auto pso = kind == format::PipelineKind::compute ? dearchiver->unpack_compute(name)
                                                         : dearchiver->unpack_graphics(name);
        if (!pso) errors[t] = pso.error().message;
      }
      for (const auto& s : signatures)
        if (auto sig = dearchiver->unpack_signature(s); !sig) errors[t] = sig.error().message;
    });
  for (auto& t : threads) t.join();
  for (const auto& e : errors) EXPECT_EQ(e, "");
  // Both unpack_all calls see one pipeline per name, and the same ones.
  ASSERT_EQ(all[0].size(), pipelines.size());
  EXPECT_EQ(std::set<const UnpackedPipeline*>(all[0].begin(), all[0].end()),
            std::set<const UnpackedPipeline*>(all[1].begin(), all[1].end()));
  for (const UnpackedPipeline* p : all[0]) EXPECT_NE(p->pipeline, VK_NULL_HANDLE) << p->name;
}

// Patched variants from several threads at once (each alternating between two specialization values,
// so the threads meet on the same variants), then released while other threads keep unpacking: the
// variant table and the released places are shared state.
TEST_F(TsanUnpack, ConcurrentVariantsAndReleasesAgree) {
  auto dearchiver = Dearchiver::create(vk_->device_context());
  ASSERT_TRUE(dearchiver);
  std::string compute;
  for (const auto& path : corpus_archives_without_run_time_state()) {
    auto archive = Archive::from_file(path);
    ASSERT_TRUE(archive) << archive.error().message;
    for (const auto& p : detail::ArchiveAccess::contents(*archive).pipelines)
      if (compute.empty() && p.kind == format::PipelineKind::compute) compute = p.name;
    ASSERT_TRUE(dearchiver->add_archive(std::move(*archive)));
  }
  ASSERT_FALSE(compute.empty());
  // Two settled states that differ (the first constant's value, when there is one; else identical).
  auto variant = [](int which) {
    return [which](PatchableState& s) {
      if (!s.constants.empty() && s.constants[0].size == 4) s.constants[0].value[0] = uint8_t(which + 1);
    };
  };
  std::vector<std::string> errors(4);
  std::vector<std::thread> threads;
  for (size_t t = 0; t < 4; ++t)
    threads.emplace_back([&, t] {
      for (int i = 0; i < 40; ++i) {
        auto pso = dearchiver->unpack_compute(compute, variant(i % 2));
        if (!pso) {
          errors[t] = pso.error().message;
          return;
        }
        // Threads 2 and 3 release what they got every tenth time.
        if (t >= 2 && i % 10 == 9) (void)dearchiver->release(*pso);  // may have gone already: refused
      }
    });
  for (auto& t : threads) t.join();
  for (const auto& e : errors) EXPECT_EQ(e, "");
  // Afterwards the table still answers: the same state twice is one live pipeline.
  auto a = dearchiver->unpack_compute(compute, variant(0));
  auto b = dearchiver->unpack_compute(compute, variant(0));
  ASSERT_TRUE(a && b);
  EXPECT_EQ(*a, *b);
  EXPECT_NE((*a)->pipeline, VkPipeline(VK_NULL_HANDLE));
}

// Unpack jobs running while other threads wait for their pipelines, unpack the same ones singly (which
// wait for the job's), start a second job that meets the first on every pipeline, and finally destroy
// the Dearchiver with a third job still creating: every shared structure of the jobs at once.
TEST_F(TsanUnpack, AsynchronousJobsWaitersAndSingleUnpacksAgree) {
  std::vector<std::pair<std::string, format::PipelineKind>> pipelines;
  std::optional<UnpackJob> last;
  {
    auto dearchiver = Dearchiver::create(vk_->device_context());
    ASSERT_TRUE(dearchiver);
    std::set<std::string> names;
    for (const auto& path : corpus_archives_without_run_time_state()) {
      auto archive = Archive::from_file(path);
      ASSERT_TRUE(archive) << archive.error().message;
      for (const auto& p : detail::ArchiveAccess::contents(*archive).pipelines)
        if (names.insert(p.name).second) pipelines.emplace_back(p.name, p.kind);
      ASSERT_TRUE(dearchiver->add_archive(std::move(*archive)));
    }
    std::atomic<size_t> progressed{0};
    UnpackAllOptions options;
    options.threads = 2;
    options.progress = [&](const UnpackProgress&) { ++progressed; };
    auto first = dearchiver->unpack_all_async(options);
    ASSERT_TRUE(first) << first.error().message;
    std::vector<std::string> errors(4);
    std::vector<std::vector<const UnpackedPipeline*>> seen(4);
    std::vector<std::thread> threads;
    for (size_t t = 0; t < 2; ++t)  // waiters, in opposite orders
      threads.emplace_back([&, t] {
        for (size_t i = 0; i < pipelines.size(); ++i) {
          const std::string& name = pipelines[t == 0 ? i : pipelines.size() - 1 - i].first;
          auto got = first->wait(name);
          if (got)
            seen[t].push_back(*got);
          else
            errors[t] = got.error().message;
        }
      });
    threads.emplace_back([&] {  // single unpacks of what the job is making
      for (const auto& [name, kind] : pipelines) {
        auto got = kind == format::PipelineKind::compute ? dearchiver->unpack_compute(name)
                                                         : dearchiver->unpack_graphics(name);
        if (got)
          seen[2].push_back(*got);
        else
          errors[2] = got.error().message;
      }
    });
    threads.emplace_back([&] {  // a second job meeting the first on every pipeline
      auto second = dearchiver->unpack_all(UnpackAllOptions{});
      if (!second)
        errors[3] = second.error().message;
      else if (!second->ok())
        errors[3] = second->failures.front().error.message;
      else
        seen[3] = second->pipelines;
    });
    for (auto& t : threads) t.join();
    for (const auto& e : errors) EXPECT_EQ(e, "");
    UnpackReport report = first->wait_all();
    EXPECT_TRUE(report.ok());
    EXPECT_EQ(progressed.load(), pipelines.size());
    // Everyone got the same pipeline per name: one set of pipelines, made once.
    const std::set<const UnpackedPipeline*> made(report.pipelines.begin(), report.pipelines.end());
    EXPECT_EQ(made.size(), pipelines.size());
    for (const auto& list : seen)
      EXPECT_EQ(std::set<const UnpackedPipeline*>(list.begin(), list.end()), made);
    // A patched job still running when the Dearchiver goes.
    UnpackAllOptions patched;
    patched.threads = 2;
    patched.patch = [](const ObjectInfo&, PatchableState& s) {
      if (!s.constants.empty() && s.constants[0].size == 4) s.constants[0].value[0] ^= 1;
    };
    auto running = dearchiver->unpack_all_async(patched);
    ASSERT_TRUE(running) << running.error().message;
    last.emplace(std::move(*running));
  }
  UnpackReport after = last->wait_all();
  EXPECT_EQ(after.failures.size(), pipelines.size());
  for (const auto& f : after.failures) EXPECT_EQ(f.error.code, ErrorCode::cancelled) << f.error.message;
}

}  // namespace
}  // namespace statepack::testing
