// The one thread pool of statepack: runs work(i) for every i in [0, count) on up to `threads` threads
// (0: one per core), the calling thread included, each taking the next index until none is left.
// Used by the packager (compiling shaders, finalising modules) and by Dearchiver::unpack_all.
#pragma once

#include <algorithm>
#include <atomic>
#include <cstddef>
#include <cstdint>
#include <thread>
#include <vector>

namespace statepack::detail {

// How many threads run `count` jobs when `threads` are asked for (0: one per core): never more than
// there are jobs, at least one.
inline size_t pool_size(size_t count, uint32_t threads) {
  const size_t n = threads ? threads : std::max(1u, std::thread::hardware_concurrency());
  return std::min(n, std::max<size_t>(count, 1));
}

template <class Work>
void parallel_for(size_t count, uint32_t threads, Work&& work) {
  std::atomic<size_t> next{0};
  auto worker = [&] {
    for (size_t i = next++; i < count; i = next++) work(i);
  };
  const size_t n = pool_size(count, threads);
  std::vector<std::thread> pool;
  for (size_t i = 1; i < n; ++i) pool.emplace_back(worker);
  worker();
  for (auto& t : pool) t.join();
}

}  // namespace statepack::detail
