// A SPIRV-Cross context that frees itself (and everything made from it) on every path.
#pragma once

#include <spirv_cross_c.h>

namespace statepack::packager {

struct SpirvCrossContext {
  spvc_context handle = nullptr;
  SpirvCrossContext() = default;
  SpirvCrossContext(const SpirvCrossContext&) = delete;
  SpirvCrossContext& operator=(const SpirvCrossContext&) = delete;
  ~SpirvCrossContext() {
    if (handle) spvc_context_destroy(handle);
  }
};

}  // namespace statepack::packager
