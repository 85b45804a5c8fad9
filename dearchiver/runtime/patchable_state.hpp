// The archive's pipeline state as the modify callback sees it (PatchableState), and back: dynamic states
// between VkDynamicState and the archive's bit mask, specialization constants by name.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "format/archive_format.hpp"
#include "statepack/dearchiver.hpp"

namespace statepack::detail {

// The archive's bit for a dynamic state statepack supports (archive_format.hpp has the numbering).
std::optional<uint32_t> dynamic_state_bit(VkDynamicState state);
VkDynamicState dynamic_state_of_bit(uint32_t index);
std::string dynamic_state_name(VkDynamicState state);  // "VK_DYNAMIC_STATE_VIEWPORT", ... (vk_enum_names.hpp)

// A pipeline's archived state; constants one entry per name, stages merged.
PatchableState to_patchable(const format::Pipeline& pipeline);
std::vector<SpecializationConstant> constants_of(const format::Pipeline& pipeline);
// The constants a callback settled, checked against the archive's: known names, unchanged sizes.
Result<std::vector<SpecializationConstant>> settle_constants(const format::Pipeline& pipeline,
                                                             std::vector<SpecializationConstant> given);

}  // namespace statepack::detail
