// "Did you mean": the suggestions a reader needs, and work bounded whatever the input (issue 24:
// 200,000 candidates or very long names once took more than 30 s).
#include "support/suggest.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cctype>
#include <random>
#include <string>
#include <vector>

namespace statepack::detail {
namespace {

// The plain dynamic program, case-insensitive: what the banded one must agree with within its bound.
size_t reference_distance(const std::string& a, const std::string& b) {
  std::vector<std::vector<size_t>> d(a.size() + 1, std::vector<size_t>(b.size() + 1));
  for (size_t i = 0; i <= a.size(); ++i) d[i][0] = i;
  for (size_t j = 0; j <= b.size(); ++j) d[0][j] = j;
  for (size_t i = 1; i <= a.size(); ++i)
    for (size_t j = 1; j <= b.size(); ++j) {
      bool same = std::tolower(static_cast<unsigned char>(a[i - 1])) ==
                  std::tolower(static_cast<unsigned char>(b[j - 1]));
      d[i][j] = std::min({d[i - 1][j] + 1, d[i][j - 1] + 1, d[i - 1][j - 1] + (same ? 0 : 1)});
    }
  return d[a.size()][b.size()];
}

TEST(Suggest, FindsTyposAndCase) {
  std::vector<std::string> names = {"RGBA8_UNORM", "RGBA16_FLOAT", "BGRA8_UNORM", "D32_FLOAT"};
  EXPECT_EQ(closest_names("rgba8_unorm", names), (std::vector<std::string>{"RGBA8_UNORM", "BGRA8_UNORM"}));
  EXPECT_EQ(did_you_mean("D32_FLAOT", names), " (did you mean 'D32_FLOAT'?)");
  EXPECT_EQ(did_you_mean("completely different", names), "");
  EXPECT_EQ(did_you_mean("", names), "");
}

TEST(Suggest, AgreesWithThePlainEditDistanceWithinItsBound) {
  std::mt19937 rng(7);
  const std::string alphabet = "abcAB_";
  auto random_name = [&](size_t length) {
    std::string s;
    for (size_t i = 0; i < length; ++i) s += alphabet[rng() % alphabet.size()];
    return s;
  };
  for (int trial = 0; trial < 3000; ++trial) {
    std::string name = random_name(1 + rng() % 30);
    // A candidate near the name (a few random edits) or unrelated.
    std::string candidate = name;
    for (auto edits = rng() % 12; edits > 0 && !candidate.empty(); --edits) {
      size_t at = rng() % candidate.size();
      switch (rng() % 3) {
        case 0:
          candidate.erase(at, 1);
          break;
        case 1:
          candidate.insert(at, 1, alphabet[rng() % alphabet.size()]);
          break;
        default:
          candidate[at] = alphabet[rng() % alphabet.size()];
      }
    }
    if (candidate.empty()) continue;
    const size_t bound = std::clamp<size_t>(name.size() / 3, 2, 8);
    const bool close = reference_distance(name, candidate) <= bound;
    std::vector<std::string> one = {candidate};
    EXPECT_EQ(!closest_names(name, one).empty(), close) << "'" << name << "' vs '" << candidate << "'";
  }
}

TEST(Suggest, ClosestComeFirst) {
  std::vector<std::string> names = {"shadow_mapx", "shadow_map_", "shadow_map"};
  EXPECT_EQ(closest_names("shadow_map", names)[0], "shadow_map");
}

// 200,000 candidates of the name's own length (none can be skipped by length), and a name of a
// megabyte: each call returns (its work is bounded: unbounded, the megabyte name against 200,000
// candidates is 3e12 steps, which ctest's time-out would catch), and a close candidate is still found.
TEST(Suggest, HostileSizesStayBounded) {
  std::vector<std::string> many;
  many.push_back("pipeline_00000x");
  for (int i = 0; i < 200000; ++i) {
    std::string n = std::to_string(i);
    many.push_back("pipelin" + std::string(8 - n.size(), 'q') + n);
  }
  auto close = closest_names("pipeline_00000", many);
  ASSERT_FALSE(close.empty());
  EXPECT_EQ(close[0], "pipeline_00000x");
  EXPECT_LE(close.size(), 3u);
  std::string huge(1 << 20, 'a');
  EXPECT_TRUE(closest_names(huge, many).empty());
  std::vector<std::string> huge_candidates(100, huge);
  EXPECT_TRUE(closest_names("aaaa", huge_candidates).empty());
}

}  // namespace
}  // namespace statepack::detail
