// statepack archive format, version 1: the decoded model and the codec.
//
// This is the one place the on-disk format is defined; the packager encodes with it and the
// dearchiver decodes with it. The byte layout is specified in docs/archive-format.md and, table by
// table, next to the code in archive_format.cpp.
//
// Vulkan enum values (VkFormat, VkDescriptorType, VkShaderStageFlags, ...) are stored as their numeric
// values: the Vulkan ABI fixes them, so they are as stable as our own codes would be.
#pragma once

#include <algorithm>
#include <array>
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "statepack/result.hpp"

namespace statepack::format {

inline constexpr std::array<uint8_t, 8> kMagic = {0x89, 'S', 'P', 'K', '\r', '\n', 0x1A, '\n'};
inline constexpr uint32_t kFormatVersion = 4;          // what this code reads (1 to 4) and writes at most
inline constexpr uint32_t kOldestReadableVersion = 2;  // what a reader must at least understand
// Version 3 adds the TESS section (patch control points), written only when a pipeline tessellates; such
// an archive needs a version-3 reader (a version-2 reader would create its pipelines without the count).
// Archives without tessellation stay readable by version-2 readers.
inline constexpr uint32_t kTessellationVersion = 3;
// Version 4 adds the GLTS section (patch control points of OpenGL pipelines), written only when an
// OpenGL pipeline tessellates; such an archive says version 4 in both fields (a version-3 reader would
// find tessellation stages it refuses). Every other archive is written as version 3, byte for byte as
// before.
inline constexpr uint32_t kGlTessellationVersion = 4;
inline constexpr uint32_t kWrittenVersion = 3;  // the format_version of archives without GLTS
// Version 2 adds the PEXT and SPEC sections (dynamic states, specialization constants). A version-1
// reader would ignore them and create pipelines with other dynamic states and no constants, so
// archives written now need a version-2 reader; version-1 archives still read (no PEXT: the legacy
// dynamic states, viewport and scissor).
inline constexpr uint32_t kHeaderSize = 64;
inline constexpr uint32_t kBlobAlignment = 16;  // SPIR-V blobs start on 16-byte file offsets
inline constexpr uint32_t kNone = 0xFFFFFFFFu;  // "no index" in index fields
inline constexpr uint32_t kMaxColorTargets = 8;

enum Backend : uint32_t {
  kBackendVulkan = 1u << 0,
  kBackendOpenGL = 1u << 1,  // SPIR-V for OpenGL 4.5 + ARB_gl_spirv (Contents::gl_pipelines)
};

enum class PipelineKind : uint32_t { graphics = 0, compute = 1 };

struct Sampler {
  uint32_t mag_filter = 1, min_filter = 1;               // VkFilter (LINEAR)
  uint32_t mipmap_mode = 1;                              // VkSamplerMipmapMode (LINEAR)
  uint32_t address_u = 2, address_v = 2, address_w = 2;  // VkSamplerAddressMode (CLAMP_TO_EDGE)
  float mip_lod_bias = 0;
  uint32_t anisotropy_enable = 0;
  float max_anisotropy = 1;
  uint32_t compare_enable = 0;
  uint32_t compare_op = 0;  // VkCompareOp
  float min_lod = 0, max_lod = 3.402823466e+38f;
  uint32_t border_color = 0;  // VkBorderColor
  uint32_t unnormalized_coordinates = 0;
  bool operator==(const Sampler&) const = default;
};

struct Binding {
  std::string name;  // the shader's resource name (block name or variable name)
  uint32_t binding = 0;
  uint32_t descriptor_type = 0;  // VkDescriptorType
  uint32_t count = 1;
  uint32_t stage_flags = 0;            // VkShaderStageFlags
  uint32_t immutable_sampler = kNone;  // index into Contents::samplers, used for every array element
  bool operator==(const Binding&) const = default;
};

// A VkDescriptorType (core types 0-10) in words, for messages: "storage buffer", "combined image sampler".
// The one table of them: the codec's checks and the packager's messages both use it.
const char* descriptor_type_name(uint32_t descriptor_type);

// A descriptor set layout. A named one is a resource signature (unpackable by name); an unnamed
// one is a pipeline's implicit layout.
struct SetLayout {
  std::string name;
  uint32_t binding_index = 0;     // a signature's set number (DRSN BindingIndex)
  std::vector<Binding> bindings;  // sorted by binding number
  bool operator==(const SetLayout&) const = default;
};

struct Shader {
  std::string name;
  uint32_t stage = 0;  // VkShaderStageFlagBits
  uint32_t blob = 0;   // index into Contents::spirv
  std::string entry_point;
};

struct VertexBinding {
  uint32_t binding = 0, stride = 0;
  uint32_t input_rate = 0;  // VkVertexInputRate
  bool operator==(const VertexBinding&) const = default;
};

struct VertexAttribute {
  uint32_t location = 0, binding = 0;
  uint32_t format = 0;  // VkFormat
  uint32_t offset = 0;
  bool operator==(const VertexAttribute&) const = default;
};

struct Attachment {
  uint32_t format = 0, samples = 1;
  uint32_t load_op = 0, store_op = 0;  // VkAttachmentLoadOp / StoreOp
  uint32_t stencil_load_op = 2, stencil_store_op = 1;
  uint32_t initial_layout = 0, final_layout = 0;  // VkImageLayout
  bool operator==(const Attachment&) const = default;
};

struct AttachmentRef {
  uint32_t attachment = kNone;  // VK_ATTACHMENT_UNUSED when kNone
  uint32_t layout = 0;          // VkImageLayout
  bool operator==(const AttachmentRef&) const = default;
};

struct Subpass {
  std::vector<AttachmentRef> inputs, colors, resolves;  // resolves: empty or one per color
  AttachmentRef depth_stencil;
  std::vector<uint32_t> preserve;
  bool operator==(const Subpass&) const = default;
};

struct Dependency {
  uint32_t src_subpass = 0, dst_subpass = 0;  // kNone = VK_SUBPASS_EXTERNAL
  uint32_t src_stages = 0, dst_stages = 0;    // VkPipelineStageFlags
  uint32_t src_access = 0, dst_access = 0;    // VkAccessFlags
  uint32_t flags = 0;                         // VkDependencyFlags
  bool operator==(const Dependency&) const = default;
};

struct RenderPass {
  std::string name;
  std::vector<Attachment> attachments;
  std::vector<Subpass> subpasses;
  std::vector<Dependency> dependencies;
  bool operator==(const RenderPass&) const = default;
};

struct BlendAttachment {
  uint32_t enable = 0;
  uint32_t src_color = 1;  // VkBlendFactor (ONE)
  uint32_t dst_color = 0;  // VkBlendFactor (ZERO)
  uint32_t color_op = 0;   // VkBlendOp (ADD)
  uint32_t src_alpha = 1;
  uint32_t dst_alpha = 0;
  uint32_t alpha_op = 0;
  uint32_t write_mask = 0xF;  // VkColorComponentFlags
  bool operator==(const BlendAttachment&) const = default;
};

struct StencilOpState {
  uint32_t fail_op = 0, pass_op = 0, depth_fail_op = 0;  // VkStencilOp (KEEP)
  uint32_t compare_op = 7;                               // VkCompareOp (ALWAYS)
  bool operator==(const StencilOpState&) const = default;
};

// Fixed-function state of a graphics pipeline. Viewport and scissor are always dynamic.
struct GraphicsState {
  uint32_t topology = 3;      // VkPrimitiveTopology (TRIANGLE_LIST)
  uint32_t polygon_mode = 0;  // VkPolygonMode (FILL)
  uint32_t cull_mode = 2;     // VkCullModeFlags (BACK)
  uint32_t front_face = 1;    // VkFrontFace (CLOCKWISE, as Diligent's FrontCounterClockwise=false)
  uint32_t depth_clamp = 0;   // 1 when DepthClipEnable=false
  float depth_bias = 0, depth_bias_clamp = 0, depth_bias_slope = 0;
  uint32_t depth_test = 1, depth_write = 1;
  uint32_t depth_compare = 1;  // VkCompareOp (LESS)
  uint32_t stencil_test = 0;
  uint32_t stencil_read_mask = 0xFF, stencil_write_mask = 0xFF;
  StencilOpState front, back;
  uint32_t samples = 1;  // VkSampleCountFlagBits
  uint32_t sample_mask = 0xFFFFFFFFu;
  uint32_t alpha_to_coverage = 0;
  uint32_t color_count = 0;
  std::array<uint32_t, kMaxColorTargets> color_formats{};  // VkFormat
  uint32_t depth_stencil_format = 0;                       // VkFormat
  std::array<BlendAttachment, kMaxColorTargets> blend{};
  std::vector<VertexBinding> vertex_bindings;
  std::vector<VertexAttribute> vertex_attributes;
  // Control points per patch, with topology PATCH_LIST only (else 0). In the TESS section, not GFXS, so
  // that GFXS records keep their format-1 size.
  uint32_t patch_control_points = 0;
  bool operator==(const GraphicsState&) const = default;
};

// Dynamic states are a bit mask in the archive: bit i for VkDynamicState i (0..8, Vulkan 1.0's), and
// bit 9 + k for VK_DYNAMIC_STATE_CULL_MODE + k (Vulkan 1.3's extended dynamic state, 1000267000 + k).
inline constexpr uint32_t kDynamicViewport = 1u << 0, kDynamicScissor = 1u << 1, kDynamicLineWidth = 1u << 2,
                          kDynamicDepthBias = 1u << 3, kDynamicBlendConstants = 1u << 4,
                          kDynamicDepthBounds = 1u << 5, kDynamicStencilCompareMask = 1u << 6,
                          kDynamicStencilWriteMask = 1u << 7, kDynamicStencilReference = 1u << 8;
inline constexpr uint32_t kDynamicExtendedFirstBit = 9;  // VK_DYNAMIC_STATE_CULL_MODE
// Extended states statepack supports: cull mode, front face, topology, depth test/write/compare, depth
// bounds test, stencil test and op (not the *_WITH_COUNT or vertex-stride ones: viewport and scissor
// stay plain dynamic states and vertex strides are fixed by the input layout).
inline constexpr uint32_t kDynamicExtendedMask = (1u << 9) | (1u << 10) | (1u << 11) | (1u << 15) |
                                                 (1u << 16) | (1u << 17) | (1u << 18) | (1u << 19) |
                                                 (1u << 20);
inline constexpr uint32_t kDynamicAllowed = 0x1FFu | kDynamicExtendedMask;
// What every graphics pipeline has: viewport and scissor, and what Diligent's Vulkan backend adds (blend
// constants, stencil reference). Archives of format 1 made viewport and scissor dynamic only.
inline constexpr uint32_t kDynamicDefault =
    kDynamicViewport | kDynamicScissor | kDynamicBlendConstants | kDynamicStencilReference;
inline constexpr uint32_t kDynamicLegacy = kDynamicViewport | kDynamicScissor;

// One specialization constant of one stage of a pipeline (SPEC record).
struct SpecConstant {
  std::string name;          // as the shader names it (OpName), for the modify callback
  uint32_t stage = 0;        // VkShaderStageFlagBits of the shader it specialises
  uint32_t constant_id = 0;  // the SpecId decoration
  uint32_t size = 4;         // bytes: 4 (bool as VkBool32, int, uint, float) or 8 (double, 64-bit int)
  uint64_t value = 0;        // the value's bytes, little-endian; `size` of them are used
  bool operator==(const SpecConstant&) const = default;
};

struct Pipeline {
  std::string name;
  PipelineKind kind = PipelineKind::graphics;
  std::vector<uint32_t> shaders;      // indices into Contents::shaders
  std::vector<uint32_t> set_layouts;  // per descriptor set number: index into set_layouts or kNone
  uint32_t push_constant_size = 0;
  uint32_t push_constant_stages = 0;
  GraphicsState graphics;  // meaningful for graphics pipelines only
  // A graphics pipeline's render pass: index into Contents::render_passes, kNone for dynamic rendering.
  // (Stored at the end of the GFXS record, where format 1 put it.)
  uint32_t render_pass = kNone;
  uint32_t subpass = 0;
  // Format 2 (PEXT section, parallel to PIPE): dynamic states of a graphics pipeline, and the
  // specialization constants of every stage.
  uint32_t dynamic_states = kDynamicDefault;
  std::vector<SpecConstant> constants;
  bool operator==(const Pipeline&) const = default;
};

// --- the OpenGL backend block (sections GLPI, GLSH, GLBD) -------------------------------------------
// Readers that do not know these sections ignore them and read the Vulkan part, so the block changes
// neither the format version nor the oldest readable one. SPIR-V blobs, graphics states (GFXS) and
// specialization constants (SPEC) share the Vulkan part's pools.

// OpenGL has no descriptor sets: each kind of resource has its own binding numbers.
enum class GlNamespace : uint32_t {
  uniform_buffer = 0,  // glBindBufferBase(GL_UNIFORM_BUFFER, binding, ...)
  storage_buffer = 1,  // glBindBufferBase(GL_SHADER_STORAGE_BUFFER, binding, ...)
  texture = 2,         // texture unit: glBindTextureUnit(binding, ...) (combined samplers, texel buffers)
  image = 3,           // image unit: glBindImageTexture(binding, ...) (storage images and texel buffers)
};
inline constexpr uint32_t kGlNamespaceCount = 4;

// Where OpenGL binds a resource of a VkDescriptorType: uniform/storage buffers (dynamic ones too),
// textures (combined samplers, uniform texel buffers), images (storage images and texel buffers); nothing
// for separate samplers and sampled images or input attachments, which OpenGL does not have. The one
// classification: the packer's layout and refusals and the reader's check use it.
std::optional<GlNamespace> gl_namespace_of(uint32_t descriptor_type);
// "uniform buffer", "storage buffer", "texture", "image" (kGlNamespaceCount names), else "unknown".
const char* gl_namespace_name(uint32_t kind);

struct GlShader {
  std::string name;
  uint32_t stage = 0;  // VkShaderStageFlagBits, as Shader::stage
  uint32_t blob = 0;   // index into Contents::spirv: SPIR-V compiled for OpenGL
  std::string entry_point;
  bool operator==(const GlShader&) const = default;
};

// A resource of a GL pipeline by the name its shaders give it, and where the application binds it.
struct GlBinding {
  std::string name;
  uint32_t kind = 0;  // GlNamespace
  uint32_t binding = 0;
  uint32_t count = 1;   // array elements (consecutive bindings from `binding`)
  uint32_t stages = 0;  // VkShaderStageFlags of the stages that use it
  bool operator==(const GlBinding&) const = default;
};

struct GlPipeline {
  std::string name;
  PipelineKind kind = PipelineKind::graphics;
  std::vector<GlShader> shaders;    // one per stage
  std::vector<GlBinding> bindings;  // sorted by (kind, binding)
  GraphicsState graphics;           // graphics pipelines only; no render pass in OpenGL
  std::vector<SpecConstant> constants;
  bool operator==(const GlPipeline&) const = default;
};

// Everything an archive holds. When decoding, `spirv` points into the archive bytes (zero copy);
// when encoding, the caller keeps the blobs alive and unique (the packager deduplicates them).
struct Contents {
  uint32_t format_version = kWrittenVersion;  // set by decode; encode writes 3, or 4 with GLTS
  uint32_t producer_version = 0;              // packager version, VK_MAKE_API_VERSION-style packing
  uint32_t content_version = 0;               // user's version (statepack -v)
  uint32_t backends = kBackendVulkan;
  std::vector<std::span<const uint32_t>> spirv;
  std::vector<Shader> shaders;
  std::vector<uint32_t> standalone_shaders;  // indices into shaders, unpackable by name
  std::vector<Sampler> samplers;
  std::vector<SetLayout> set_layouts;
  std::vector<RenderPass> render_passes;
  std::vector<Pipeline> pipelines;
  std::vector<GlPipeline> gl_pipelines;  // the OpenGL backend; sorted by name, written only when present
};

// The record of that name in a list the archive keeps sorted by name (Contents::pipelines and
// gl_pipelines, checked on load), or null: one binary search.
template <class Record>
const Record* find_by_name(const std::vector<Record>& sorted, std::string_view name) {
  auto it = std::lower_bound(sorted.begin(), sorted.end(), name,
                             [](const Record& r, std::string_view n) { return r.name < n; });
  return it != sorted.end() && it->name == name ? &*it : nullptr;
}

// Serialises `contents`, byte for byte deterministic. Pipelines must have unique names, and so must
// standalone shaders; pipelines and standalone shaders are stored sorted by name.
std::vector<uint8_t> encode(const Contents& contents);

// Validates every offset, size, count and checksum, then decodes. `bytes` must be 4-byte aligned
// and must outlive the result's `spirv` spans.
Result<Contents> decode(std::span<const uint8_t> bytes);
// The OpenGL block's records (names, stages, binding tables, constants, graphics state), which decode
// leaves unchecked: the Vulkan runtime never reads them, and a program that does not use OpenGL then
// links none of this (check_opengl in archive_file.hpp runs it with the checks against the SPIR-V).
Result<void> validate_gl(const Contents& contents);

// XXH3-64 of the bytes; the hash used for blob content and the whole-archive checksum.
uint64_t hash_bytes(std::span<const uint8_t> bytes);

// Every field of a record, lists included, as bytes: equal records (operator==) have equal keys, so
// writers can find a record already stored in constant time (T: Shader, Sampler, SetLayout, RenderPass).
template <class T>
std::string record_key(const T& record);

}  // namespace statepack::format
