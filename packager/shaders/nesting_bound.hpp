#pragma once
// Bounds on how deeply a shader nests, checked before the compiler runs, and the stack the compiler runs
// on. glslang's parsers and tree walks (and SPIRV-Cross's, for OpenGL) recurse once per nesting level:
// a 20,000-term sum `v+v+...` (40 KB) overflowed an 8 MiB stack. So every compile runs on a thread
// whose stack is sized for the largest nesting these bounds let through, and text that passes them is
// refused by name before any recursion starts. The bounds are far beyond what hand-written or
// generated shaders need: glslang's own GLSL parser stops at 10,000 nested brackets.
#include <cstddef>
#include <cstdint>
#include <functional>
#include <string>
#include <string_view>

namespace statepack::packager {

// Brackets ( [ { a file may nest in its own text (comments aside): bounds the preprocessor's recursion
// through nested macro arguments, F(F(F(...))).
inline constexpr size_t kMaxBracketDepth = 10000;
// The most a preprocessed shader may nest by nesting_bound's measure.
inline constexpr size_t kMaxNesting = size_t(1) << 18;
// The compile thread's stack: kMaxNesting levels at up to 4 KiB each (the deepest recursion measured
// takes under 1 KiB per level). Reserved, not used: pages are touched only as deep as a shader goes.
inline constexpr size_t kCompileStackBytes = size_t(1) << 30;

// How deep brackets nest in `text`, comments skipped; `line` is where the deepest one opens.
size_t bracket_depth(std::string_view text, size_t* line = nullptr);

// An upper bound on how deeply the compiler's tree nests for a preprocessed text, without parsing it:
// at every point, the non-blank characters of each statement still open there, summed over the
// brackets open there (a left-associative chain `v+v+...` nests once per operator, so its length
// bounds its depth). ';' and a block's end close a statement; ',' separates elements where it is a
// list (a call's or a constructor's arguments, an initializer's elements), not where it is the comma
// operator, whose chain nests like any other. Directive lines (#version, #line, ...) do not count.
size_t nesting_bound(std::string_view preprocessed);

// Whether nesting_bound of `source` preprocessed after `preamble` is known to be within kMaxNesting
// without preprocessing it (which costs as much as a third of a small shader's compile). nesting_bound
// is at most a text's non-blank characters plus one, and preprocessing can only remove or shorten text
// when the source defines no macro and includes nothing (neither word appears in it, nor a backslash,
// which could splice a directive across lines) and every macro the preamble defines is object-like with a
// value no longer than its name (the environment's 1s and empty ones, VARIANT=12); glslang's predefined
// macros expand to numbers no longer than their names, or (__LINE__, 8 characters) at most 10 digits. So such
// a text within half the bound, counted with its preamble, needs no preprocess to pass.
bool within_bound_unpreprocessed(std::string_view source, std::string_view preamble);

// Runs `work` on a thread with a `stack_bytes` stack and waits for it: the calling thread itself when it
// is one of parallel_on_stacks' with such a stack, else a new one. False (with `error` set) when the
// system cannot make such a thread; `work` then has not run.
bool run_on_stack(size_t stack_bytes, const std::function<void()>& work, std::string& error);

// Runs work(i) for every i in [0, count) on up to `threads` threads (0: one per core) with
// `stack_bytes` stacks, each taking the next index; the calling thread waits, and the first exception
// thrown is rethrown to it once every thread has stopped. The threads live for the whole loop, so the
// stack pages a compile touched and the thread's malloc arena serve every job it takes: a thread per
// job faulted both in again (~15 us a page on a VM). When the system makes no such thread the loop runs
// on the calling thread, where run_on_stack tries again for each job and says why it cannot.
void parallel_on_stacks(size_t count, uint32_t threads, size_t stack_bytes,
                        const std::function<void(size_t)>& work);

}  // namespace statepack::packager
