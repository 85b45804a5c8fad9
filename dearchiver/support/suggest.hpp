// "Did you mean" suggestions for unknown names, shared by the packager and the dearchiver.
#pragma once

#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace statepack::detail {

// Candidates within a small edit distance of `name`, closest first (at most `limit`).
std::vector<std::string> closest_names(std::string_view name, std::span<const std::string> candidates,
                                       size_t limit = 3);

// " (did you mean 'a' or 'b'?)" or "" when nothing is close.
std::string did_you_mean(std::string_view name, std::span<const std::string> candidates);

}  // namespace statepack::detail
