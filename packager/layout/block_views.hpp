// Views of one buffer block declared per stage. Vulkan lets each stage of a pipeline declare its own view
// of a uniform block or of the push constants: the members it uses, at their offsets (a vertex shader's
// `mat4 mvp` at 0, a pixel shader's `float roughness` at 64). OpenGL links one definition per block, so
// the OpenGL backend merges the views into one, written into every stage's module, when the members agree
// wherever they overlap; members that truly conflict (two types at one offset, overlapping bytes) are an
// error naming both stages. The same analysis warns on Vulkan when two stages' views of one name conflict.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace statepack::packager {

// One stage's view: its module and the block's OpVariable in it.
struct BlockView {
  std::vector<uint32_t>* spirv;
  uint32_t variable;
  std::string shader;  // "vertex shader 'X'", for messages
};

// "" when the views' members agree wherever they overlap; else the conflict, naming both members and
// their shaders ("'mat4 projection' at offset 0 in vertex shader 'A' and 'float heightScale' at offset 0
// in pixel shader 'B'").
std::string block_views_conflict(const std::vector<BlockView>& views);

// Rewrites each view's block as the union of all views' members (sorted by offset), so that every module
// declares one identical definition. Returns "" or why it could not (a conflict, or a use of the block
// this does not rewrite, such as loading it whole).
std::string merge_block_views(const std::vector<BlockView>& views);

}  // namespace statepack::packager
