// A pipeline's OpenGL binding table, from its shaders compiled for OpenGL. OpenGL has no descriptor
// sets: uniform buffers, storage buffers, textures and images each have binding numbers of their own.
// Resources are numbered per kind in the order the shaders declare them (set, then binding), merged by
// name across stages, and the modules' Binding decorations are patched to those numbers (DescriptorSet
// to 0), so the archive's SPIR-V and table agree and the runtime binds by name.
#pragma once

#include <cstdint>
#include <vector>

#include "format/archive_format.hpp"
#include "notation/diagnostics.hpp"
#include "notation/notation.hpp"
#include "pipeline_layout.hpp"

namespace statepack::packager {

struct GlLayout {
  std::vector<format::GlBinding> bindings;           // sorted by (kind, binding)
  std::vector<std::vector<uint32_t>> patched_spirv;  // per stage, in the order given
};

// False (with an error naming the pipeline and resource) for what OpenGL cannot express: separate
// samplers or sampled images, input attachments, push constants, one name of two kinds or sizes.
bool build_gl_layout(const PipelineDesc& pipeline, const std::vector<StageInput>& stages, GlLayout& out,
                     Diagnostics& diag);

// What OpenGL 4.5 guarantees of a namespace's binding points in a program (GL_MAX_UNIFORM_BUFFER_BINDINGS
// 84, GL_MAX_SHADER_STORAGE_BUFFER_BINDINGS 8, GL_MAX_COMBINED_TEXTURE_IMAGE_UNITS 80, GL_MAX_IMAGE_UNITS 8).
uint32_t gl_guaranteed_units(format::GlNamespace kind);

// "" when `bindings` (a shader's or a pipeline's, by descriptor type and count) fit what OpenGL 4.5
// guarantees; else what they need, in the user's words ("80 texture units ... 'tex' is an array of 100").
std::string gl_units_exceeded(const std::vector<ReflectedBinding>& bindings);

}  // namespace statepack::packager
