// The OpenGL backend from any source that packs for Vulkan. A shader's Vulkan SPIR-V is translated by
// SPIRV-Cross to GLSL 4.50 (separate images and samplers combined, gl_VertexIndex/gl_InstanceIndex
// remapped, descriptor sets flattened, push constants as a uniform block), which glslang's OpenGL client
// then compiles to SPIR-V for GL_ARB_gl_spirv. The GL program so runs the code the Vulkan pipeline
// runs, from HLSL as from Vulkan GLSL, with no rewrite of the source (docs/cli.md, "The OpenGL backend").
#pragma once

#include <cstdint>
#include <map>
#include <span>
#include <string>
#include <vector>

namespace statepack::packager {

// The binding-table name of a pipeline's push constants in the OpenGL block: a uniform block that holds
// the same bytes at the same offsets (`$` keeps it apart from every name a shader can declare).
inline constexpr const char* kGlPushConstantsName = "$PushConstants";

struct GlTranslation {
  std::string glsl;  // GLSL 4.50 (no Vulkan semantics) for glslang's OpenGL client
  // (GL namespace, binding number) each resource got in `glsl` -> its name in the OpenGL binding table:
  // the Vulkan resource's name; a combined image sampler takes its image's name (Diligent's convention:
  // `g_Tex` with `g_Tex_sampler`, or any image sampled with one sampler only), else `image_sampler`.
  // Each namespace (uniform buffers, storage buffers, textures, images) is numbered from 0 in the Vulkan
  // declaration order (set, then binding), so the GL table keeps that order.
  std::map<std::pair<uint32_t, uint32_t>, std::string> name_of_binding;
  std::string unsupported;  // what OpenGL 4.5 cannot express, by name (nothing translated)
  std::string error;        // SPIRV-Cross refused the module: its message
};

// `sampler_suffix`: Diligent's CombinedSamplerSuffix ("_sampler").
GlTranslation translate_for_opengl(std::span<const uint32_t> vulkan_spirv, const std::string& sampler_suffix);

}  // namespace statepack::packager
