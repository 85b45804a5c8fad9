#include "allocation_budget.hpp"

#include <cstdlib>
#include <new>

#if defined(__SANITIZE_ADDRESS__) || defined(__SANITIZE_THREAD__)
#define STATEPACK_KEEP_OPERATOR_NEW 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer) || __has_feature(thread_sanitizer) || __has_feature(memory_sanitizer)
#define STATEPACK_KEEP_OPERATOR_NEW 1
#endif
#endif

namespace statepack::packager {
namespace {

struct ThreadBudget {
  bool active = false;
  bool exhausted = false;
  uint64_t used = 0;
  uint64_t limit = 0;
};

// constinit: the counter must work for allocations made before main, without a guard.
constinit thread_local ThreadBudget t_budget;

}  // namespace

bool allocation_budget_enforced() {
#ifdef STATEPACK_KEEP_OPERATOR_NEW
  return false;
#else
  return true;
#endif
}

AllocationBudget::AllocationBudget(uint64_t bytes) {
  t_budget = ThreadBudget{true, false, 0, bytes};
}
AllocationBudget::~AllocationBudget() {
  t_budget.active = false;
}
void AllocationBudget::raise(uint64_t bytes) {
  t_budget.limit = bytes > UINT64_MAX - t_budget.limit ? UINT64_MAX : t_budget.limit + bytes;
}
bool AllocationBudget::exhausted() const {
  return t_budget.exhausted;
}
uint64_t AllocationBudget::used() const {
  return t_budget.used;
}
uint64_t AllocationBudget::limit() const {
  return t_budget.limit;
}

}  // namespace statepack::packager

#ifndef STATEPACK_KEEP_OPERATOR_NEW
namespace {

void* counted_allocation(std::size_t size) {
  auto& budget = statepack::packager::t_budget;
  if (budget.active) {
    budget.used += size;
    if (budget.used > budget.limit) {
      budget.active = false;  // once: whatever the unwinding allocates is not refused again
      budget.exhausted = true;
      throw std::bad_alloc();
    }
  }
  for (;;) {
    if (void* p = std::malloc(size ? size : 1)) return p;
    std::new_handler handler = std::get_new_handler();
    if (!handler) throw std::bad_alloc();
    handler();
  }
}

}  // namespace

// The replaceable allocation functions ([new.delete]); the aligned forms keep the library's.
void* operator new(std::size_t size) {
  return counted_allocation(size);
}
void* operator new[](std::size_t size) {
  return counted_allocation(size);
}
void* operator new(std::size_t size, const std::nothrow_t&) noexcept {
  try {
    return counted_allocation(size);
  } catch (const std::bad_alloc&) {
    return nullptr;
  }
}
void* operator new[](std::size_t size, const std::nothrow_t&) noexcept {
  try {
    return counted_allocation(size);
  } catch (const std::bad_alloc&) {
    return nullptr;
  }
}
void operator delete(void* p) noexcept {
  std::free(p);
}
void operator delete[](void* p) noexcept {
  std::free(p);
}
void operator delete(void* p, std::size_t) noexcept {
  std::free(p);
}
void operator delete[](void* p, std::size_t) noexcept {
  std::free(p);
}
void operator delete(void* p, const std::nothrow_t&) noexcept {
  std::free(p);
}
void operator delete[](void* p, const std::nothrow_t&) noexcept {
  std::free(p);
}
#endif
