// The compile stages' threads (packager/shaders/nesting_bound.hpp): every job once, each on a thread
// with the compiler's stack that lives for the whole loop (run_on_stack inside a job makes no thread of
// its own), and an exception thrown by a job reaches the caller once every thread has stopped.
#include <gtest/gtest.h>
#include <pthread.h>

#include <algorithm>
#include <atomic>
#include <cctype>
#include <chrono>
#include <mutex>
#include <set>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include "shaders/nesting_bound.hpp"

namespace statepack::packager {
namespace {

// The stack size of the calling thread.
size_t own_stack_bytes() {
  pthread_attr_t attributes;
  size_t bytes = 0;
  if (pthread_getattr_np(pthread_self(), &attributes) != 0) return 0;
  pthread_attr_getstacksize(&attributes, &bytes);
  pthread_attr_destroy(&attributes);
  return bytes;
}

TEST(CompileStackTest, EveryJobRunsOnceOnALongLivedThreadWithTheCompilersStack) {
  constexpr size_t kJobs = 1000;
  std::vector<std::atomic<int>> runs(kJobs);
  std::mutex mutex;
  std::set<pthread_t> threads;
  std::atomic<int> small_stacks{0}, nested_elsewhere{0};
  parallel_on_stacks(kJobs, 2, kCompileStackBytes, [&](size_t i) {
    ++runs[i];
    if (own_stack_bytes() < kCompileStackBytes) ++small_stacks;
    const pthread_t self = pthread_self();
    std::string error;
    run_on_stack(
        kCompileStackBytes, [&] { nested_elsewhere += pthread_equal(self, pthread_self()) ? 0 : 1; }, error);
    std::lock_guard lock(mutex);
    threads.insert(self);
  });
  for (size_t i = 0; i < kJobs; ++i) EXPECT_EQ(runs[i], 1) << "job " << i;
  EXPECT_EQ(small_stacks, 0);
  EXPECT_EQ(nested_elsewhere, 0);  // already on such a stack: no thread per job
  EXPECT_GE(threads.size(), 1u);
  EXPECT_LE(threads.size(), 2u);                // two threads for a thousand jobs, not a thread each
  EXPECT_FALSE(threads.count(pthread_self()));  // the caller's stack is the main thread's
}

TEST(CompileStackTest, AJobsExceptionReachesTheCallerAfterEveryThreadStopped) {
  constexpr size_t kJobs = 1000;  // 2 ms each: two seconds of work the failure cuts short
  std::atomic<int> running{0}, ran{0};
  try {
    parallel_on_stacks(kJobs, 2, kCompileStackBytes, [&](size_t i) {
      ++running;
      ++ran;
      if (i == 3) {
        --running;
        throw std::runtime_error("job 3 failed");
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(2));
      --running;
    });
    FAIL() << "no exception";
  } catch (const std::runtime_error& e) {
    EXPECT_STREQ(e.what(), "job 3 failed");
  }
  EXPECT_EQ(running, 0);  // nothing still running when the caller got it
  EXPECT_LT(ran, int(kJobs) / 2) << "the other thread went on taking jobs";
}

TEST(CompileStackTest, NoJobsMakesNoThread) {
  bool ran = false;
  parallel_on_stacks(0, 2, kCompileStackBytes, [&](size_t) { ran = true; });
  EXPECT_FALSE(ran);
}

// The shortcut within_bound_unpreprocessed: a source that defines no macro, includes nothing and has no
// backslash, after a preamble whose macros are object-like and expand no longer than their names, passes
// unpreprocessed when half the bound holds its non-blank characters; anything else is preprocessed (and
// measured). Its premise: the measure never passes a text's non-blank characters plus one.
TEST(NestingBoundTest, OnlyASourcePreprocessingCannotGrowSkipsThePreprocess) {
  const std::string plain = "#version 450\nvoid main() { float v = 1.0; v = v + v; }\n";
  const std::string environment =
      "#define GLSLANG\n#define DESKTOP_GL 1\n# define VARIANT 12\nlayout(std140) uniform;\n";
  EXPECT_TRUE(within_bound_unpreprocessed(plain, environment));
  for (const char* grows :
       {"#define F(x) (x)\n", "#if defined(X)\n#endif\n", "#include \"a.glsl\"\n", "#def\\\nine F(x) (x)\n"})
    EXPECT_FALSE(within_bound_unpreprocessed(plain + grows, environment)) << grows;
  for (const char* preamble :
       {"#define F(x) (x)\n", "#define A ((((\n", "#define AB 123\n", "#define\tB 1 // one\n"})
    EXPECT_FALSE(within_bound_unpreprocessed(plain, preamble)) << preamble;
  EXPECT_TRUE(within_bound_unpreprocessed(plain, "#define ABC 123\n#pragma pack_matrix(row_major)\n"));
  std::string sum = "v";
  while (sum.size() < kMaxNesting / 2) sum += "+v";
  EXPECT_FALSE(within_bound_unpreprocessed("void main() { v = " + sum + "; }\n", ""));
  EXPECT_TRUE(
      within_bound_unpreprocessed("void main() { v = " + sum.substr(0, kMaxNesting / 4) + "; }\n", ""));
  auto non_blank = [](const std::string& text) {
    return size_t(std::count_if(text.begin(), text.end(), [](char c) { return !std::isspace(c); }));
  };
  for (const std::string& text :
       {plain, environment + plain, std::string("{{{{((([[[ a ]]])))}}}}"), std::string("f(a, b, (c + d));"),
        "void main() { v = " + sum + "; }", std::string(5000, '(') + std::string(5000, ')')})
    EXPECT_LE(nesting_bound(text), non_blank(text) + 1) << text.substr(0, 40);
}

}  // namespace
}  // namespace statepack::packager
