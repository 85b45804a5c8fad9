#include "suggest.hpp"

#include <algorithm>
#include <atomic>
#include <cstdint>

namespace statepack::detail {
namespace {

// The work is bounded so that an error message is always fast, whatever the input (200,000 candidate
// names, names of megabytes, thousands of errors):
// - names longer than kMaxComparedLength get no suggestion (a typo is found in a name one can read);
// - a suggestion is at most kMaxEdits edits away, so only candidates of about the name's length are
//   compared, each in a band of 2 * kMaxEdits + 1 cells per row;
// - one call compares at most kCellsPerCall cells (about 20 ms here), candidates in their given order
//   (with 200,000 candidates of 13 characters, the first ~17,000);
// - a process spends at most kCellsPerProcess cells on suggestions in all (about 0.6 s here): beyond
//   that, messages come without a suggestion. A packager run with --max-errors 0 over a hostile file
//   thus stays linear in its errors.
constexpr size_t kMaxComparedLength = 256;
constexpr size_t kMaxEdits = 8;
constexpr uint64_t kCellsPerCall = 2'000'000;
constexpr uint64_t kCellsPerProcess = 64'000'000;
std::atomic<uint64_t> cells_spent{0};

// ASCII lower case, inline (std::tolower is a call into the C library per cell).
char lower(char c) {
  return c >= 'A' && c <= 'Z' ? char(c - 'A' + 'a') : c;
}

// Levenshtein distance, case-insensitive ("rgba8_unorm" finds "RGBA8_UNORM"; `a` is already in lower
// case), computed only within `limit` of the diagonal; any distance above `limit` is reported as
// limit + 1. Adds the cells it computed to `cells`; `row` is scratch space.
size_t bounded_edit_distance(std::string_view a, std::string_view b, size_t limit, uint64_t& cells,
                             std::vector<size_t>& row) {
  const size_t over = limit + 1;
  if ((a.size() > b.size() ? a.size() - b.size() : b.size() - a.size()) > limit) return over;
  row.assign(b.size() + 1, over);
  for (size_t j = 0; j <= std::min(b.size(), limit); ++j) row[j] = j;
  for (size_t i = 1; i <= a.size(); ++i) {
    const size_t from = i > limit ? i - limit : 1, to = std::min(b.size(), i + limit);
    size_t diagonal = row[from - 1];  // row[i-1][from-1]
    row[from - 1] = from - 1 == 0 && i <= limit ? i : over;
    size_t best = row[from - 1];
    for (size_t j = from; j <= to; ++j) {
      const size_t above = row[j];
      row[j] = std::min({above + 1, row[j - 1] + 1, diagonal + (a[i - 1] == lower(b[j - 1]) ? 0 : 1), over});
      diagonal = above;
      best = std::min(best, row[j]);
    }
    if (to < b.size()) row[to + 1] = over;  // the band's right edge, for the next row
    cells += to + 1 - from;
    if (best > limit) return over;  // every path through this row is already too far
  }
  return std::min(row[b.size()], over);
}

}  // namespace

std::vector<std::string> closest_names(std::string_view name, std::span<const std::string> candidates,
                                       size_t limit) {
  if (name.empty() || name.size() > kMaxComparedLength) return {};
  const size_t threshold = std::clamp<size_t>(name.size() / 3, 2, kMaxEdits);
  std::string lowered(name);
  for (char& ch : lowered) ch = lower(ch);
  std::vector<std::pair<size_t, std::string_view>> scored;
  std::vector<size_t> row;
  uint64_t cells = 0;
  for (const auto& candidate : candidates) {
    if (cells >= kCellsPerCall || cells_spent.load(std::memory_order_relaxed) >= kCellsPerProcess) break;
    if (candidate.size() > kMaxComparedLength) continue;
    size_t distance = bounded_edit_distance(lowered, candidate, threshold, cells, row);
    if (distance <= threshold) scored.emplace_back(distance, candidate);
  }
  cells_spent.fetch_add(cells, std::memory_order_relaxed);
  std::stable_sort(scored.begin(), scored.end(), [](auto& x, auto& y) { return x.first < y.first; });
  std::vector<std::string> result;
  for (size_t i = 0; i < scored.size() && i < limit; ++i) result.emplace_back(scored[i].second);
  return result;
}

std::string did_you_mean(std::string_view name, std::span<const std::string> candidates) {
  auto close = closest_names(name, candidates);
  if (close.empty()) return "";
  std::string text = " (did you mean ";
  for (size_t i = 0; i < close.size(); ++i) {
    if (i > 0) text += i + 1 == close.size() ? " or " : ", ";
    text += "'" + close[i] + "'";
  }
  return text + "?)";
}

}  // namespace statepack::detail
