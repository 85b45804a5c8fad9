// ThreadSanitizer run of the dearchiver: several archives added, unpack_all on worker threads while
// other threads unpack single objects through the same Dearchiver. Built by tests/CMakeLists.txt as
// dearchiver_tsan_tests, which compiles the dearchiver's sources with -fsanitize=thread; the Vulkan
// loader, the validation layer and lavapipe are not instrumented (see tests/tsan.supp).
#include <algorithm>
#include <set>
#include <thread>

#include "common/vulkan_test_fixture.hpp"
#include "format/archive_format.hpp"
#include "runtime/archive_access.hpp"

namespace statepack::testing {
namespace {

class TsanUnpack : public VulkanTest {};

TEST_F(TsanUnpack, ConcurrentUnpackAllAndSingleUnpacksAgree) {
  auto dearchiver = Dearchiver::create({vk_->physical_device, vk_->device});
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

}  // namespace
}  // namespace statepack::testing
