// A uniform block turned into the module's push-constant block, as Diligent's Vulkan backend does for
// a resource flagged INLINE_CONSTANTS: the variable, and every pointer the shader derives from it, move
// to the PushConstant storage class, and its DescriptorSet and Binding decorations go. The block's
// member offsets stay, so the values pushed are laid out exactly as the uniform buffer's were.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace statepack::packager {

// Converts the uniform-block variable `variable` (an OpVariable result id) of `spirv`. Returns "" or
// what stands in the way (not a uniform block; the module already has push constants; a pointer to the
// block used in a way this does not follow, such as a function argument).
std::string uniform_block_to_push_constants(std::vector<uint32_t>& spirv, uint32_t variable);

}  // namespace statepack::packager
