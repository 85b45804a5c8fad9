#include "huge_pages.hpp"

#include <malloc.h>
#include <sys/mman.h>
#include <unistd.h>

#include <algorithm>
#include <condition_variable>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "shaders/allocation_budget.hpp"

namespace statepack::packager {
namespace {

constexpr int kTopPad = 64 << 20;              // each heap grows in 64 MiB steps...
constexpr int kTrimThreshold = 1 << 30;        // ...and keeps them (a pack is short-lived)
constexpr size_t kMostArenas = 16;             // thread heaps made ahead, at most
constexpr size_t kGrowthBlock = 120 << 10;     // under glibc's first mmap threshold (128 KiB): from the heap
constexpr size_t kMostGrowthBlocks = 128;      // (free chunks of the main heap are taken first)
constexpr size_t kHugePage = size_t{2} << 20;  // x86-64's and AArch64's (4 KiB base pages) PMD size

// Whether the kernel gives huge pages to memory that asks (madvise) or to all: "[never]" says neither.
bool kernel_has_huge_pages() {
  std::ifstream in("/sys/kernel/mm/transparent_hugepage/enabled");
  std::string modes;
  return std::getline(in, modes) && modes.find("[never]") == std::string::npos;
}

struct Mapping {
  uintptr_t from = 0, to = 0;
  bool anonymous = false;  // no file and no name such as [stack] or [heap]
};

std::vector<Mapping> read_maps() {
  std::vector<Mapping> maps;
  std::ifstream in("/proc/self/maps");
  for (std::string line; std::getline(in, line);) {
    unsigned long long from = 0, to = 0, inode = 0;
    int name_at = 0;
    if (std::sscanf(line.c_str(), "%llx-%llx %*s %*s %*s %llu %n", &from, &to, &inode, &name_at) != 3)
      continue;
    const bool named = name_at > 0 && static_cast<size_t>(name_at) < line.size();
    maps.push_back({static_cast<uintptr_t>(from), static_cast<uintptr_t>(to), inode == 0 && !named});
  }
  return maps;
}

// The anonymous mapping holding `block`: [from, to), or an empty range when the block is in no anonymous
// mapping. A thread heap made with the 64 MiB top pad is one read-write mapping (neighbouring heaps may
// show as one); nothing beside it is taken (a thread stack's guard page, another reservation).
std::pair<uintptr_t, uintptr_t> heap_around(const std::vector<Mapping>& maps, const void* block) {
  const auto at = reinterpret_cast<uintptr_t>(block);
  for (const Mapping& m : maps)
    if (at >= m.from && at < m.to)
      return m.anonymous ? std::pair{m.from, m.to} : std::pair<uintptr_t, uintptr_t>{};
  return {};
}

bool advise(uintptr_t from, uintptr_t to) {
  return to - from >= kHugePage && ::madvise(reinterpret_cast<void*>(from), to - from, MADV_HUGEPAGE) == 0;
}

// The advice holds for pages not yet touched; the huge page around `at` was touched before it (a heap's
// own header, the blocks in use), so it is made one now (Linux 6.1's MADV_COLLAPSE; older kernels say
// EINVAL and leave it on 4 KiB pages), when it lies within [from, to).
void collapse(uintptr_t at, uintptr_t from, uintptr_t to) {
#ifndef MADV_COLLAPSE
  constexpr int MADV_COLLAPSE = 25;  // (glibc 2.36's headers predate it)
#endif
  const uintptr_t start = at & ~(kHugePage - 1);
  if (start >= from && start + kHugePage <= to)
    ::madvise(reinterpret_cast<void*>(start), kHugePage, MADV_COLLAPSE);
}

// Grows the main heap now (by the top pad: blocks taken until the break moves), advises all of it, and
// collapses the huge pages that hold what was touched before: the old break's and the new top's. Left
// on 4 KiB pages: a main heap with more than kMostGrowthBlocks blocks' worth free already (the break
// does not move), and what it grows by after this (a new mapping, which the advice does not cover).
bool advise_main_heap() {
  const auto before = reinterpret_cast<uintptr_t>(::sbrk(0));
  std::vector<void*> blocks;
  while (blocks.size() < kMostGrowthBlocks && reinterpret_cast<uintptr_t>(::sbrk(0)) == before)
    if (void* block = std::malloc(kGrowthBlock))
      blocks.push_back(block);
    else
      break;
  const auto after = reinterpret_cast<uintptr_t>(::sbrk(0));
  const uintptr_t last = blocks.empty() ? 0 : reinterpret_cast<uintptr_t>(blocks.back());
  for (void* block : blocks) std::free(block);
  if (before == static_cast<uintptr_t>(-1) || after <= before) return false;
  for (const Mapping& heap : read_maps())
    if (heap.from < before && heap.to == after) {
      if (!advise(heap.from, heap.to)) return false;
      collapse(before - 1, heap.from, heap.to);
      if (((before - 1) ^ (last + kGrowthBlock)) >= kHugePage)
        collapse(last + kGrowthBlock, heap.from, heap.to);
      return true;
    }
  return false;
}

// Makes up to `count` thread heaps at once (a thread's first malloc takes a heap of its own while the
// others live), advises each, and lets the threads end: glibc keeps their heaps on its free list and
// hands them to the next threads that allocate. Returns how many distinct heaps were advised (threads
// that had to share one, past glibc's arena limit, count once). Nothing here allocates on those threads
// but their one block, and they are released and joined whatever the main thread meets.
size_t advise_thread_heaps(size_t count) {
  std::mutex mutex;
  std::condition_variable changed;
  std::vector<void*> blocks(count, nullptr);
  size_t ready = 0;
  bool done = false;
  std::vector<std::thread> threads;
  threads.reserve(count);
  auto release = [&] {
    {
      std::lock_guard lock(mutex);
      done = true;
    }
    changed.notify_all();
    for (auto& thread : threads) thread.join();
  };
  size_t advised = 0;
  try {
    for (size_t i = 0; i < count; ++i)
      threads.emplace_back([&, i] {
        void* block = std::malloc(1);
        std::unique_lock lock(mutex);
        blocks[i] = block, ++ready;
        changed.notify_all();
        changed.wait(lock, [&] { return done; });
        lock.unlock();
        std::free(block);
      });
  } catch (...) {  // (no thread: fewer heaps ahead)
  }
  try {
    {
      std::unique_lock lock(mutex);
      changed.wait(lock, [&] { return ready == threads.size(); });
    }
    const std::vector<Mapping> maps = read_maps();
    std::vector<uintptr_t> pages;  // the huge page of each heap's first block, once
    for (const void* block : blocks) {
      const auto [from, to] = heap_around(maps, block);
      const uintptr_t page = reinterpret_cast<uintptr_t>(block) & ~(kHugePage - 1);
      if (from == to || std::find(pages.begin(), pages.end(), page) != pages.end() || !advise(from, to))
        continue;
      collapse(reinterpret_cast<uintptr_t>(block), from, to);
      pages.push_back(page);
    }
    advised = pages.size();
  } catch (...) {  // (out of memory reading the maps: left on 4 KiB pages)
  }
  release();
  return advised;
}

}  // namespace

size_t use_huge_pages(size_t threads) {
  const char* tunables = std::getenv("GLIBC_TUNABLES");
  if (tunables && std::string(tunables).find("glibc.malloc.hugetlb") != std::string::npos) return 0;
  if (const char* preload = std::getenv("LD_PRELOAD"); preload && *preload) return 0;
  // (A sanitizer build allocates with the sanitizer's own malloc, which has no such heaps.)
  if (!allocation_budget_enforced() || !kernel_has_huge_pages() || ::access("/proc/self/maps", R_OK) != 0)
    return 0;
  if (::mallopt(M_TOP_PAD, kTopPad) != 1 || ::mallopt(M_TRIM_THRESHOLD, kTrimThreshold) != 1) return 0;
  const size_t main_heap = advise_main_heap() ? 1 : 0;
  // The pack's other threads at once: its pool's (-t, less this one), the compiler's two warm-ups, the
  // cache's flush and the archive's record: -t plus three.
  return main_heap + advise_thread_heaps(std::min(kMostArenas, threads + 3));
}

}  // namespace statepack::packager
