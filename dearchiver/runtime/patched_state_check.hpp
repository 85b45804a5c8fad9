// What a modify (or unpack_all patch) callback leaves in a PatchableState, checked before any of it
// reaches Vulkan, as the archive's own values are checked at load.
#pragma once

#include <optional>
#include <string_view>

#include "statepack/dearchiver.hpp"

namespace statepack::detail {

// Every enumeration and flag of the graphics state within Vulkan 1.0's core values (the archive holds
// no others), for the render targets in use: formats, sample count, blend factors, ops and write masks,
// polygon mode, cull mode, front face, compare and stencil ops, and at most 8 render targets. Device
// support (formats, sample counts, features) is checked afterwards, by the code that checks the
// archive's values. Dynamic states and constants are settled separately. The error names the pipeline,
// the field and the value.
std::optional<Error> check_patched_state(std::string_view pipeline, const PatchableState& state);

}  // namespace statepack::detail
