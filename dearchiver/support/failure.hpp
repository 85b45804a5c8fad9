// Errors made on cold paths. The runtime's checks build their messages only when a check fails; made
// through failure(), a cold function, the compiler treats every path that builds one as never taken:
// that code is optimised for size and moved out of the load's hot code (issue 39: the messages were
// most of the runtime's bytes), while the checks themselves stay as fast.
#pragma once

#include <vulkan/vulkan_core.h>

#include <string>

#include "statepack/result.hpp"

namespace statepack::detail {

[[gnu::cold]] Error failure(ErrorCode code, std::string message, VkResult vk_result = VK_SUCCESS);

// ErrorCode::corrupt, "corrupt archive: <message>": what the archive's decode and checks report.
[[gnu::cold]] Error corrupt(std::string message);

}  // namespace statepack::detail
