#pragma once
// Preprocessor directive lines of a shader text, found without preprocessing it: for the checks that
// look at a text before glslang does (its #version line, the macros a preamble defines).
#include <algorithm>
#include <string_view>

namespace statepack::packager {

// Calls on_directive(directive, line) for each line of `text` whose first non-blank is '#', `directive`
// being what follows the '#' without its leading blanks, until it returns true; whether one did.
template <class OnDirective>
bool for_each_directive(std::string_view text, OnDirective&& on_directive) {
  size_t start = 0;
  while (start < text.size()) {
    size_t end = text.find('\n', start);
    if (end == std::string_view::npos) end = text.size();
    const std::string_view line = text.substr(start, end - start);
    start = end + 1;
    const size_t hash = line.find_first_not_of(" \t");
    if (hash == std::string_view::npos || line[hash] != '#') continue;
    std::string_view directive = line.substr(hash + 1);
    directive.remove_prefix(std::min(directive.size(), directive.find_first_not_of(" \t")));
    if (on_directive(directive, line)) return true;
  }
  return false;
}

}  // namespace statepack::packager
