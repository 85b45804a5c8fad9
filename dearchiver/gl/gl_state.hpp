// The archive's Vulkan-valued graphics state in OpenGL enums. Every value is mapped through a table: an
// enum GL has no counterpart for (or an unknown one) is an error naming the pipeline, never a cast.
#pragma once

#include <epoxy/gl.h>

#include <string_view>

#include "format/archive_format.hpp"
#include "statepack/gl_dearchiver.hpp"

namespace statepack::gl::detail {

struct Extensions {
  bool polygon_offset_clamp = false;  // GL 4.6 or GL_ARB_polygon_offset_clamp (glPolygonOffsetClamp)
};

Result<FixedFunctionState> translate_state(const format::GraphicsState& state, std::string_view pipeline,
                                           const Extensions& extensions);

Result<VertexInput> translate_vertex_input(const format::GraphicsState& state, std::string_view pipeline);

// VkShaderStageFlagBits to the glCreateShader type, or 0.
GLenum shader_type(uint32_t vk_stage);

}  // namespace statepack::gl::detail
