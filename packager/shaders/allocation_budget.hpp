#pragma once
// A bound on the memory one shader's compilation may allocate, so that a macro that expands
// exponentially ("#define A1 (A0+A0)" forty times, or F(F(F(...))) with "#define F(x) (x+x)") ends as
// an error naming the shader instead of growing the packer by gigabytes or running for hours.
//
// glslang expands macros itself and offers no limit, and its token streams are lazy, so the bound is
// put where every expansion must pass: the global operator new. While a budget is active on a thread,
// every allocation that thread makes is counted (gross bytes, not net: a macro expanded inside an #if
// allocates and frees its input stream a billion times and never grows); the allocation that would
// pass the budget throws std::bad_alloc once, and the budget is off from then on.
//
// glslang is built without exceptions, so the throw unwinds its frames without running their
// destructors: what it held at that point (at most the budget) leaks once per such shader. Its only
// lock is taken while it builds its built-in symbol tables, which allocate far less than the budget's
// floor, so it is never held across the throw.
#include <cstdint>

namespace statepack::packager {

// Whether this build counts allocations (sanitizer builds keep their own operator new: no budget).
bool allocation_budget_enforced();

class AllocationBudget {
 public:
  // Starts counting this thread's allocations against `bytes`; a nested budget is not supported.
  explicit AllocationBudget(uint64_t bytes);
  ~AllocationBudget();
  AllocationBudget(const AllocationBudget&) = delete;
  AllocationBudget& operator=(const AllocationBudget&) = delete;

  // Allows `bytes` more (an #include read during the compile brings its own share).
  void raise(uint64_t bytes);
  // Whether an allocation was refused for passing the budget.
  bool exhausted() const;
  // The bytes counted so far.
  uint64_t used() const;
  uint64_t limit() const;
};

}  // namespace statepack::packager
