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

// What api_guard (runtime/api_guard.hpp) returns for an exception, out of every entry point's code.
// Neither throws: when building the message fails, a short one that needs no allocation is returned.
[[gnu::cold]] Error out_of_memory_in(const char* entry_point) noexcept;
[[gnu::cold]] Error unexpected_exception_in(const char* entry_point, const char* what) noexcept;

}  // namespace statepack::detail
