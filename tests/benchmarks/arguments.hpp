// Command-line numbers of the benchmarks, read strictly: "-1", "3x" or "" is a usage error (exit 2), not
// a default chosen in silence as atoi would.
#pragma once

#include <charconv>
#include <optional>
#include <string_view>

namespace statepack::benchmarks {

// The whole of `text` as a decimal number in [1, max].
inline std::optional<int> positive_count(std::string_view text, int max = 1000000) {
  int value = 0;
  auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), value);
  if (error != std::errc() || end != text.data() + text.size() || value < 1 || value > max)
    return std::nullopt;
  return value;
}

}  // namespace statepack::benchmarks
