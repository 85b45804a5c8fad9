// What makes two patched unpacks of one pipeline the same Vulkan pipeline: its name and the state the
// modify or patch callback settled (render targets, blending, rasterizer, depth-stencil, samples,
// dynamic states, specialization constants), field by field, so that the same patch returns the
// pipeline made before, whatever callback produced it (dearchiver.cpp's variants).
#pragma once

#include <string>
#include <string_view>

#include "pipeline_plan.hpp"

namespace statepack::detail {

std::string variant_key(std::string_view pipeline, const Plan& plan);

}  // namespace statepack::detail
