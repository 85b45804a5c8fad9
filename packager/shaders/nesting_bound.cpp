#include "nesting_bound.hpp"

#include <pthread.h>

#include <algorithm>
#include <atomic>
#include <cctype>
#include <cstring>
#include <exception>
#include <mutex>
#include <vector>

#include "directive_lines.hpp"
#include "support/parallel_for.hpp"

namespace statepack::packager {
namespace {

// Walks `text` skipping // and /* */ comments, calling on_char(c, at) for every other character.
template <class OnChar>
void for_each_code_char(std::string_view text, OnChar&& on_char) {
  for (size_t i = 0; i < text.size(); ++i) {
    if (text[i] == '/' && i + 1 < text.size() && text[i + 1] == '/') {
      while (i < text.size() && text[i] != '\n') ++i;
      if (i < text.size()) on_char('\n', i);
      continue;
    }
    if (text[i] == '/' && i + 1 < text.size() && text[i + 1] == '*') {
      const size_t end = text.find("*/", i + 2);
      for (size_t k = i; k < std::min(end, text.size()); ++k)
        if (text[k] == '\n') on_char('\n', k);  // lines still count
      if (end == std::string_view::npos) return;
      i = end + 1;
      continue;
    }
    on_char(text[i], i);
  }
}

bool is_word_char(char c) {
  return std::isalnum(static_cast<unsigned char>(c)) || c == '_';
}

}  // namespace

size_t bracket_depth(std::string_view text, size_t* deepest_line) {
  size_t depth = 0, deepest = 0, line = 1;
  for_each_code_char(text, [&](char c, size_t) {
    if (c == '\n') ++line;
    if (c == '(' || c == '[' || c == '{') {
      if (++depth > deepest) {
        deepest = depth;
        if (deepest_line) *deepest_line = line;
      }
    } else if ((c == ')' || c == ']' || c == '}') && depth > 0) {
      --depth;
    }
  });
  return deepest;
}

size_t nesting_bound(std::string_view text) {
  struct Level {
    size_t chars = 0;   // of the statement open at this level
    bool list = false;  // ',' separates elements here
  };
  std::vector<Level> open(1);
  size_t total = 0, worst = 0;
  bool line_start = true, directive = false;
  char previous = 0;  // the last character that is not blank
  std::string word, last_word;
  auto close_statement = [&] {
    total -= open.back().chars;
    open.back().chars = 0;
  };
  for_each_code_char(text, [&](char c, size_t) {
    if (c == '\n') {
      line_start = true, directive = false;
      return;
    }
    if (std::isspace(static_cast<unsigned char>(c))) return;
    if (line_start && c == '#') directive = true;
    line_start = false;
    if (directive) return;
    if (is_word_char(c)) {
      word += c;
    } else if (!word.empty()) {
      last_word = std::move(word);
      word.clear();
    }
    if (c == '(' || c == '[' || c == '{') {
      // A '(' after a name (not a statement keyword) or after ']' opens arguments; '{' opens a block or
      // an initializer, whose elements are listed.
      const bool call = c == '(' && (is_word_char(previous) || previous == ']') && last_word != "if" &&
                        last_word != "while" && last_word != "for" && last_word != "switch" &&
                        last_word != "return";
      open.push_back({0, call || c == '{'});
    } else if (c == ')' || c == ']' || c == '}') {
      if (open.size() > 1) {
        total -= open.back().chars;
        open.pop_back();
      }
      if (c == '}') close_statement();
    } else if (c == ';' || (c == ',' && open.back().list)) {
      close_statement();
    } else {
      ++open.back().chars;
      ++total;
    }
    previous = c;
    worst = std::max(worst, total + open.size());
  });
  return worst;
}

namespace {

size_t non_blank(std::string_view text) {
  return size_t(std::count_if(text.begin(), text.end(),
                              [](char c) { return !std::isspace(static_cast<unsigned char>(c)); }));
}

// Whether each macro `preamble` defines is object-like with a value of no more non-blank characters than
// its name: each expansion then replaces a name with no more (by induction, also where the value names
// other macros, which expand no longer than their names).
bool preamble_macros_shrink(std::string_view preamble) {
  const bool grows = for_each_directive(preamble, [](std::string_view directive, std::string_view) {
    if (!directive.starts_with("define")) return false;
    const size_t name = directive.find_first_not_of(" \t", 6);
    if (name == std::string_view::npos || name == 6) return true;  // (not "#define NAME")
    size_t name_end = name;
    while (name_end < directive.size() && is_word_char(directive[name_end])) ++name_end;
    return name_end == name ||
           (name_end < directive.size() && directive[name_end] == '(') ||  // function-like
           non_blank(directive.substr(name_end)) > name_end - name;
  });
  return !grows;
}

}  // namespace

bool within_bound_unpreprocessed(std::string_view source, std::string_view preamble) {
  if (source.find("define") != std::string_view::npos || source.find("include") != std::string_view::npos ||
      source.find('\\') != std::string_view::npos || preamble.find('\\') != std::string_view::npos ||
      !preamble_macros_shrink(preamble))
    return false;
  return 2 * (non_blank(source) + non_blank(preamble)) + 1 <= kMaxNesting;
}

namespace {

// The stack of the thread this runs on when parallel_on_stacks made it, else 0.
thread_local size_t t_stack_bytes = 0;

// pthread_create with a `stack_bytes` stack; the error's text, or "" when made.
std::string make_thread(pthread_t& thread, size_t stack_bytes, void* (*run)(void*), void* argument) {
  pthread_attr_t attributes;
  if (int e = pthread_attr_init(&attributes); e != 0)
    return std::string("cannot make a compile thread: ") + std::strerror(e);
  int e = pthread_attr_setstacksize(&attributes, stack_bytes);
  if (e == 0) e = pthread_create(&thread, &attributes, run, argument);
  pthread_attr_destroy(&attributes);
  if (e != 0)
    return "cannot make a compile thread with a " + std::to_string(stack_bytes >> 20) +
           " MiB stack (reserved, not used): " + std::strerror(e);
  return "";
}

}  // namespace

bool run_on_stack(size_t stack_bytes, const std::function<void()>& work, std::string& error) {
  if (t_stack_bytes >= stack_bytes) {  // already on such a stack: one of parallel_on_stacks' threads
    work();
    return true;
  }
  struct Call {
    const std::function<void()>* work;
    std::exception_ptr thrown;  // handed back to the caller's thread
  } call{&work, nullptr};
  pthread_t thread;
  error = make_thread(
      thread, stack_bytes,
      [](void* argument) -> void* {
        auto* c = static_cast<Call*>(argument);
        try {
          (*c->work)();
        } catch (...) {
          c->thrown = std::current_exception();
        }
        return nullptr;
      },
      &call);
  if (!error.empty()) return false;
  pthread_join(thread, nullptr);
  if (call.thrown) std::rethrow_exception(call.thrown);
  return true;
}

void parallel_on_stacks(size_t count, uint32_t threads, size_t stack_bytes,
                        const std::function<void(size_t)>& work) {
  struct Loop {
    const std::function<void(size_t)>* work;
    size_t count;
    size_t stack_bytes;
    std::atomic<size_t> next{0};
    std::mutex mutex;
    std::exception_ptr thrown;  // the first; the others stop taking work
  } loop{&work, count, stack_bytes};
  auto run = [](void* argument) -> void* {
    auto* l = static_cast<Loop*>(argument);
    t_stack_bytes = l->stack_bytes;
    for (size_t i = l->next++; i < l->count; i = l->next++) try {
        (*l->work)(i);
      } catch (...) {
        std::lock_guard<std::mutex> lock(l->mutex);
        if (!l->thrown) l->thrown = std::current_exception();
        l->next = l->count;
      }
    return nullptr;
  };
  const size_t n = count ? detail::pool_size(count, threads) : 0;  // (no jobs: no thread)
  std::vector<pthread_t> pool(n);
  size_t made = 0;
  while (made < n && make_thread(pool[made], stack_bytes, run, &loop).empty()) ++made;
  if (made == 0) {  // the system makes no such thread: each job says so through run_on_stack
    for (size_t i = 0; i < count; ++i) work(i);
    return;
  }
  for (size_t i = 0; i < made; ++i) pthread_join(pool[i], nullptr);
  if (loop.thrown) std::rethrow_exception(loop.thrown);
}

}  // namespace statepack::packager
