// DRSN enum strings and their Vulkan values. Matching is exact and case-sensitive, as in Diligent;
// unknown strings are errors with a suggestion (nlohmann's enum macro would silently pick the first).
#pragma once

#include <vulkan/vulkan_core.h>

#include <cstdint>
#include <span>
#include <string_view>
#include <utility>

#include "format/archive_format.hpp"

namespace statepack::packager {

using EnumEntry = std::pair<std::string_view, uint32_t>;
using EnumTable = std::span<const EnumEntry>;

// A value Vulkan cannot express: accepted by name, rejected with a reason.
inline constexpr uint32_t kUnsupportedValue = 0xFFFFFFFEu;

inline constexpr EnumEntry kTextureFormats[] = {
    {"UNKNOWN", VK_FORMAT_UNDEFINED},
    {"RGBA32_FLOAT", VK_FORMAT_R32G32B32A32_SFLOAT},
    {"RGBA32_UINT", VK_FORMAT_R32G32B32A32_UINT},
    {"RGBA32_SINT", VK_FORMAT_R32G32B32A32_SINT},
    {"RGB32_FLOAT", VK_FORMAT_R32G32B32_SFLOAT},
    {"RGB32_UINT", VK_FORMAT_R32G32B32_UINT},
    {"RGB32_SINT", VK_FORMAT_R32G32B32_SINT},
    {"RGBA16_FLOAT", VK_FORMAT_R16G16B16A16_SFLOAT},
    {"RGBA16_UNORM", VK_FORMAT_R16G16B16A16_UNORM},
    {"RGBA16_UINT", VK_FORMAT_R16G16B16A16_UINT},
    {"RGBA16_SNORM", VK_FORMAT_R16G16B16A16_SNORM},
    {"RGBA16_SINT", VK_FORMAT_R16G16B16A16_SINT},
    {"RG32_FLOAT", VK_FORMAT_R32G32_SFLOAT},
    {"RG32_UINT", VK_FORMAT_R32G32_UINT},
    {"RG32_SINT", VK_FORMAT_R32G32_SINT},
    {"RGB10A2_UNORM", VK_FORMAT_A2B10G10R10_UNORM_PACK32},
    {"RGB10A2_UINT", VK_FORMAT_A2B10G10R10_UINT_PACK32},
    {"R11G11B10_FLOAT", VK_FORMAT_B10G11R11_UFLOAT_PACK32},
    {"RGBA8_UNORM", VK_FORMAT_R8G8B8A8_UNORM},
    {"RGBA8_UNORM_SRGB", VK_FORMAT_R8G8B8A8_SRGB},
    {"RGBA8_UINT", VK_FORMAT_R8G8B8A8_UINT},
    {"RGBA8_SNORM", VK_FORMAT_R8G8B8A8_SNORM},
    {"RGBA8_SINT", VK_FORMAT_R8G8B8A8_SINT},
    {"RG16_FLOAT", VK_FORMAT_R16G16_SFLOAT},
    {"RG16_UNORM", VK_FORMAT_R16G16_UNORM},
    {"RG16_UINT", VK_FORMAT_R16G16_UINT},
    {"RG16_SNORM", VK_FORMAT_R16G16_SNORM},
    {"RG16_SINT", VK_FORMAT_R16G16_SINT},
    {"D32_FLOAT", VK_FORMAT_D32_SFLOAT},
    {"R32_FLOAT", VK_FORMAT_R32_SFLOAT},
    {"R32_UINT", VK_FORMAT_R32_UINT},
    {"R32_SINT", VK_FORMAT_R32_SINT},
    {"D24_UNORM_S8_UINT", VK_FORMAT_D24_UNORM_S8_UINT},
    {"D32_FLOAT_S8X24_UINT", VK_FORMAT_D32_SFLOAT_S8_UINT},
    {"RG8_UNORM", VK_FORMAT_R8G8_UNORM},
    {"RG8_UINT", VK_FORMAT_R8G8_UINT},
    {"RG8_SNORM", VK_FORMAT_R8G8_SNORM},
    {"RG8_SINT", VK_FORMAT_R8G8_SINT},
    {"R16_FLOAT", VK_FORMAT_R16_SFLOAT},
    {"D16_UNORM", VK_FORMAT_D16_UNORM},
    {"R16_UNORM", VK_FORMAT_R16_UNORM},
    {"R16_UINT", VK_FORMAT_R16_UINT},
    {"R16_SNORM", VK_FORMAT_R16_SNORM},
    {"R16_SINT", VK_FORMAT_R16_SINT},
    {"R8_UNORM", VK_FORMAT_R8_UNORM},
    {"R8_UINT", VK_FORMAT_R8_UINT},
    {"R8_SNORM", VK_FORMAT_R8_SNORM},
    {"R8_SINT", VK_FORMAT_R8_SINT},
    {"BGRA8_UNORM", VK_FORMAT_B8G8R8A8_UNORM},
    {"BGRA8_UNORM_SRGB", VK_FORMAT_B8G8R8A8_SRGB},
};

inline constexpr EnumEntry kShaderTypes[] = {
    {"VERTEX", VK_SHADER_STAGE_VERTEX_BIT},
    {"PIXEL", VK_SHADER_STAGE_FRAGMENT_BIT},
    {"GEOMETRY", VK_SHADER_STAGE_GEOMETRY_BIT},
    {"HULL", VK_SHADER_STAGE_TESSELLATION_CONTROL_BIT},
    {"DOMAIN", VK_SHADER_STAGE_TESSELLATION_EVALUATION_BIT},
    {"COMPUTE", VK_SHADER_STAGE_COMPUTE_BIT},
    {"AMPLIFICATION", kUnsupportedValue},
    {"MESH", kUnsupportedValue},
    {"RAY_GEN", kUnsupportedValue},
    {"RAY_MISS", kUnsupportedValue},
    {"RAY_CLOSEST_HIT", kUnsupportedValue},
    {"RAY_ANY_HIT", kUnsupportedValue},
    {"RAY_INTERSECTION", kUnsupportedValue},
    {"CALLABLE", kUnsupportedValue},
    {"TILE", kUnsupportedValue},
};

// Stages DRSN names that the Vulkan backend of statepack cannot produce (mesh, ray tracing, tile):
// bits above Vulkan's stage bits, so a flags value can say that it named one. Readers strip them (see
// stage_flags_field) and report a value that names nothing else.
inline constexpr uint32_t kStageAmplification = 1u << 24, kStageMesh = 1u << 25, kStageRayGen = 1u << 26,
                          kStageRayMiss = 1u << 27, kStageRayClosestHit = 1u << 28,
                          kStageRayAnyHit = 1u << 29, kStageRayIntersection = 1u << 30,
                          kStageCallable = 1u << 31, kStageTile = 1u << 23;
inline constexpr uint32_t kStagesRayTracing = kStageRayGen | kStageRayMiss | kStageRayClosestHit |
                                              kStageRayAnyHit | kStageRayIntersection | kStageCallable;
inline constexpr uint32_t kUnproducibleStages =
    kStageAmplification | kStageMesh | kStagesRayTracing | kStageTile;

// Shader stage flags (bit-flag enum: one string or an array). Every name and alias of Diligent's
// SHADER_TYPE, with its values.
inline constexpr EnumEntry kShaderStageFlags[] = {
    {"UNKNOWN", 0},
    {"VERTEX", VK_SHADER_STAGE_VERTEX_BIT},
    {"PIXEL", VK_SHADER_STAGE_FRAGMENT_BIT},
    {"GEOMETRY", VK_SHADER_STAGE_GEOMETRY_BIT},
    {"HULL", VK_SHADER_STAGE_TESSELLATION_CONTROL_BIT},
    {"DOMAIN", VK_SHADER_STAGE_TESSELLATION_EVALUATION_BIT},
    {"COMPUTE", VK_SHADER_STAGE_COMPUTE_BIT},
    {"AMPLIFICATION", kStageAmplification},
    {"MESH", kStageMesh},
    {"RAY_GEN", kStageRayGen},
    {"RAY_MISS", kStageRayMiss},
    {"RAY_CLOSEST_HIT", kStageRayClosestHit},
    {"RAY_ANY_HIT", kStageRayAnyHit},
    {"RAY_INTERSECTION", kStageRayIntersection},
    {"CALLABLE", kStageCallable},
    {"TILE", kStageTile},
    {"LAST", kStageTile},
    {"VS_PS", VK_SHADER_STAGE_VERTEX_BIT | VK_SHADER_STAGE_FRAGMENT_BIT},
    {"ALL_GRAPHICS", VK_SHADER_STAGE_ALL_GRAPHICS},
    {"ALL_MESH", kStageAmplification | kStageMesh | VK_SHADER_STAGE_FRAGMENT_BIT},
    {"ALL_RAY_TRACING", kStagesRayTracing},
    {"ALL", VK_SHADER_STAGE_ALL_GRAPHICS | VK_SHADER_STAGE_COMPUTE_BIT | kUnproducibleStages},
};

inline constexpr EnumEntry kPipelineTypes[] = {
    {"GRAPHICS", 0}, {"COMPUTE", 1}, {"MESH", 2}, {"RAY_TRACING", 3}, {"TILE", 4},
};

inline constexpr EnumEntry kVariableTypes[] = {{"STATIC", 0}, {"MUTABLE", 1}, {"DYNAMIC", 2}};

inline constexpr EnumEntry kSourceLanguages[] = {
    {"DEFAULT", 0},      {"HLSL", 1}, {"GLSL", 2}, {"GLSL_VERBATIM", 3}, {"MSL", 4},
    {"MSL_VERBATIM", 5}, {"MTLB", 6}, {"WGSL", 7}, {"BYTECODE", 8},
};

inline constexpr EnumEntry kShaderCompilers[] = {{"DEFAULT", 0}, {"GLSLANG", 1}, {"DXC", 2}, {"FXC", 3}};

// Diligent's SHADER_COMPILE_FLAGS. Each does what it does in Diligent's Vulkan backend with glslang, or
// has no meaning there (docs/notation.md, "Compile flags").
enum CompileFlag : uint32_t {
  kCompileEnableUnboundedArrays = 1,  // Direct3D's compilers only
  kCompileSkipReflection = 2,         // Diligent's run-time reflection; statepack reflects at pack time
  kCompileAsynchronous = 4,           // Diligent compiles on a thread pool; statepack always does
  kPackMatrixRowMajor = 8,            // #pragma pack_matrix(row_major) / layout(row_major) uniform;
  kHlslToSpirvViaGlsl = 16,           // Diligent's HLSL-to-GLSL converter first; statepack compiles directly
};
inline constexpr EnumEntry kCompileFlags[] = {
    {"NONE", 0},
    {"ENABLE_UNBOUNDED_ARRAYS", kCompileEnableUnboundedArrays},
    {"SKIP_REFLECTION", kCompileSkipReflection},
    {"ASYNCHRONOUS", kCompileAsynchronous},
    {"PACK_MATRIX_ROW_MAJOR", kPackMatrixRowMajor},
    {"HLSL_TO_SPIRV_VIA_GLSL", kHlslToSpirvViaGlsl},
};

// Diligent's N_CONTROL_POINT_PATCHLIST: read as kPatchListTopology + N, then split into
// VK_PRIMITIVE_TOPOLOGY_PATCH_LIST and N patch control points.
inline constexpr uint32_t kPatchListTopology = 0x10000;
inline constexpr EnumEntry kTopologies[] = {
    {"UNDEFINED", kUnsupportedValue},
    {"TRIANGLE_LIST", VK_PRIMITIVE_TOPOLOGY_TRIANGLE_LIST},
    {"TRIANGLE_STRIP", VK_PRIMITIVE_TOPOLOGY_TRIANGLE_STRIP},
    {"POINT_LIST", VK_PRIMITIVE_TOPOLOGY_POINT_LIST},
    {"LINE_LIST", VK_PRIMITIVE_TOPOLOGY_LINE_LIST},
    {"LINE_STRIP", VK_PRIMITIVE_TOPOLOGY_LINE_STRIP},
    {"TRIANGLE_LIST_ADJ", VK_PRIMITIVE_TOPOLOGY_TRIANGLE_LIST_WITH_ADJACENCY},
    {"TRIANGLE_STRIP_ADJ", VK_PRIMITIVE_TOPOLOGY_TRIANGLE_STRIP_WITH_ADJACENCY},
    {"LINE_LIST_ADJ", VK_PRIMITIVE_TOPOLOGY_LINE_LIST_WITH_ADJACENCY},
    {"LINE_STRIP_ADJ", VK_PRIMITIVE_TOPOLOGY_LINE_STRIP_WITH_ADJACENCY},
    {"1_CONTROL_POINT_PATCHLIST", kPatchListTopology + 1},
    {"2_CONTROL_POINT_PATCHLIST", kPatchListTopology + 2},
    {"3_CONTROL_POINT_PATCHLIST", kPatchListTopology + 3},
    {"4_CONTROL_POINT_PATCHLIST", kPatchListTopology + 4},
    {"5_CONTROL_POINT_PATCHLIST", kPatchListTopology + 5},
    {"6_CONTROL_POINT_PATCHLIST", kPatchListTopology + 6},
    {"7_CONTROL_POINT_PATCHLIST", kPatchListTopology + 7},
    {"8_CONTROL_POINT_PATCHLIST", kPatchListTopology + 8},
    {"9_CONTROL_POINT_PATCHLIST", kPatchListTopology + 9},
    {"10_CONTROL_POINT_PATCHLIST", kPatchListTopology + 10},
    {"11_CONTROL_POINT_PATCHLIST", kPatchListTopology + 11},
    {"12_CONTROL_POINT_PATCHLIST", kPatchListTopology + 12},
    {"13_CONTROL_POINT_PATCHLIST", kPatchListTopology + 13},
    {"14_CONTROL_POINT_PATCHLIST", kPatchListTopology + 14},
    {"15_CONTROL_POINT_PATCHLIST", kPatchListTopology + 15},
    {"16_CONTROL_POINT_PATCHLIST", kPatchListTopology + 16},
    {"17_CONTROL_POINT_PATCHLIST", kPatchListTopology + 17},
    {"18_CONTROL_POINT_PATCHLIST", kPatchListTopology + 18},
    {"19_CONTROL_POINT_PATCHLIST", kPatchListTopology + 19},
    {"20_CONTROL_POINT_PATCHLIST", kPatchListTopology + 20},
    {"21_CONTROL_POINT_PATCHLIST", kPatchListTopology + 21},
    {"22_CONTROL_POINT_PATCHLIST", kPatchListTopology + 22},
    {"23_CONTROL_POINT_PATCHLIST", kPatchListTopology + 23},
    {"24_CONTROL_POINT_PATCHLIST", kPatchListTopology + 24},
    {"25_CONTROL_POINT_PATCHLIST", kPatchListTopology + 25},
    {"26_CONTROL_POINT_PATCHLIST", kPatchListTopology + 26},
    {"27_CONTROL_POINT_PATCHLIST", kPatchListTopology + 27},
    {"28_CONTROL_POINT_PATCHLIST", kPatchListTopology + 28},
    {"29_CONTROL_POINT_PATCHLIST", kPatchListTopology + 29},
    {"30_CONTROL_POINT_PATCHLIST", kPatchListTopology + 30},
    {"31_CONTROL_POINT_PATCHLIST", kPatchListTopology + 31},
    {"32_CONTROL_POINT_PATCHLIST", kPatchListTopology + 32},
};

inline constexpr EnumEntry kFillModes[] = {
    {"UNDEFINED", kUnsupportedValue}, {"WIREFRAME", VK_POLYGON_MODE_LINE}, {"SOLID", VK_POLYGON_MODE_FILL}};

inline constexpr EnumEntry kCullModes[] = {{"UNDEFINED", kUnsupportedValue},
                                           {"NONE", VK_CULL_MODE_NONE},
                                           {"FRONT", VK_CULL_MODE_FRONT_BIT},
                                           {"BACK", VK_CULL_MODE_BACK_BIT}};

inline constexpr EnumEntry kComparisonFuncs[] = {
    {"UNKNOWN", kUnsupportedValue},
    {"NEVER", VK_COMPARE_OP_NEVER},
    {"LESS", VK_COMPARE_OP_LESS},
    {"EQUAL", VK_COMPARE_OP_EQUAL},
    {"LESS_EQUAL", VK_COMPARE_OP_LESS_OR_EQUAL},
    {"GREATER", VK_COMPARE_OP_GREATER},
    {"NOT_EQUAL", VK_COMPARE_OP_NOT_EQUAL},
    {"GREATER_EQUAL", VK_COMPARE_OP_GREATER_OR_EQUAL},
    {"ALWAYS", VK_COMPARE_OP_ALWAYS},
};

inline constexpr EnumEntry kStencilOps[] = {
    {"UNDEFINED", kUnsupportedValue},
    {"KEEP", VK_STENCIL_OP_KEEP},
    {"ZERO", VK_STENCIL_OP_ZERO},
    {"REPLACE", VK_STENCIL_OP_REPLACE},
    {"INCR_SAT", VK_STENCIL_OP_INCREMENT_AND_CLAMP},
    {"DECR_SAT", VK_STENCIL_OP_DECREMENT_AND_CLAMP},
    {"INVERT", VK_STENCIL_OP_INVERT},
    {"INCR_WRAP", VK_STENCIL_OP_INCREMENT_AND_WRAP},
    {"DECR_WRAP", VK_STENCIL_OP_DECREMENT_AND_WRAP},
};

inline constexpr EnumEntry kBlendFactors[] = {
    {"UNDEFINED", kUnsupportedValue},
    {"ZERO", VK_BLEND_FACTOR_ZERO},
    {"ONE", VK_BLEND_FACTOR_ONE},
    {"SRC_COLOR", VK_BLEND_FACTOR_SRC_COLOR},
    {"INV_SRC_COLOR", VK_BLEND_FACTOR_ONE_MINUS_SRC_COLOR},
    {"SRC_ALPHA", VK_BLEND_FACTOR_SRC_ALPHA},
    {"INV_SRC_ALPHA", VK_BLEND_FACTOR_ONE_MINUS_SRC_ALPHA},
    {"DEST_ALPHA", VK_BLEND_FACTOR_DST_ALPHA},
    {"INV_DEST_ALPHA", VK_BLEND_FACTOR_ONE_MINUS_DST_ALPHA},
    {"DEST_COLOR", VK_BLEND_FACTOR_DST_COLOR},
    {"INV_DEST_COLOR", VK_BLEND_FACTOR_ONE_MINUS_DST_COLOR},
    {"SRC_ALPHA_SAT", VK_BLEND_FACTOR_SRC_ALPHA_SATURATE},
    {"BLEND_FACTOR", VK_BLEND_FACTOR_CONSTANT_COLOR},
    {"INV_BLEND_FACTOR", VK_BLEND_FACTOR_ONE_MINUS_CONSTANT_COLOR},
    {"SRC1_COLOR", VK_BLEND_FACTOR_SRC1_COLOR},
    {"INV_SRC1_COLOR", VK_BLEND_FACTOR_ONE_MINUS_SRC1_COLOR},
    {"SRC1_ALPHA", VK_BLEND_FACTOR_SRC1_ALPHA},
    {"INV_SRC1_ALPHA", VK_BLEND_FACTOR_ONE_MINUS_SRC1_ALPHA},
};

inline constexpr EnumEntry kBlendOps[] = {
    {"UNDEFINED", kUnsupportedValue},   {"ADD", VK_BLEND_OP_ADD},
    {"SUBTRACT", VK_BLEND_OP_SUBTRACT}, {"REV_SUBTRACT", VK_BLEND_OP_REVERSE_SUBTRACT},
    {"MIN", VK_BLEND_OP_MIN},           {"MAX", VK_BLEND_OP_MAX},
};

// COLOR_MASK is a bit-flag enum.
inline constexpr EnumEntry kColorMasks[] = {
    {"NONE", 0},
    {"RED", VK_COLOR_COMPONENT_R_BIT},
    {"GREEN", VK_COLOR_COMPONENT_G_BIT},
    {"BLUE", VK_COLOR_COMPONENT_B_BIT},
    {"ALPHA", VK_COLOR_COMPONENT_A_BIT},
    {"RGB", VK_COLOR_COMPONENT_R_BIT | VK_COLOR_COMPONENT_G_BIT | VK_COLOR_COMPONENT_B_BIT},
    {"ALL", 0xF},
};

// Resource types of resource signatures; the descriptor type also depends on flags (see signatures.cpp).
enum ResourceType : uint32_t {
  kConstantBuffer,
  kTextureSrv,
  kBufferSrv,
  kTextureUav,
  kBufferUav,
  kSamplerResource,
  kInputAttachment,
};
inline constexpr EnumEntry kResourceTypes[] = {
    {"UNKNOWN", kUnsupportedValue},      {"CONSTANT_BUFFER", kConstantBuffer},
    {"TEXTURE_SRV", kTextureSrv},        {"BUFFER_SRV", kBufferSrv},
    {"TEXTURE_UAV", kTextureUav},        {"BUFFER_UAV", kBufferUav},
    {"SAMPLER", kSamplerResource},       {"INPUT_ATTACHMENT", kInputAttachment},
    {"ACCEL_STRUCT", kUnsupportedValue},
};

enum ResourceFlag : uint32_t {
  kNoDynamicBuffers = 1,
  kCombinedSampler = 2,
  kFormattedBuffer = 4,
  kRuntimeArray = 8,
  kGeneralInputAttachment = 16,
  kInlineConstants = 32,
};
inline constexpr EnumEntry kResourceFlags[] = {
    {"NONE", 0},
    {"NO_DYNAMIC_BUFFERS", kNoDynamicBuffers},
    {"COMBINED_SAMPLER", kCombinedSampler},
    {"FORMATTED_BUFFER", kFormattedBuffer},
    {"RUNTIME_ARRAY", kRuntimeArray},
    {"GENERAL_INPUT_ATTACHMENT", kGeneralInputAttachment},
    {"INLINE_CONSTANTS", kInlineConstants},
};

// Variable flags of ResourceLayout.Variables: INLINE_CONSTANTS makes the uniform buffer push constants;
// the others do not change the Vulkan layout.
inline constexpr uint32_t kVariableInlineConstants = 2;
inline constexpr EnumEntry kVariableFlags[] = {
    {"NONE", 0},
    {"NO_DYNAMIC_BUFFERS", 1},
    {"INLINE_CONSTANTS", kVariableInlineConstants},
    {"GENERAL_INPUT_ATTACHMENT_VK", 4},
    {"UNFILTERABLE_FLOAT_TEXTURE_WEBGPU", 8},
    {"NON_FILTERING_SAMPLER_WEBGPU", 16},
};

enum PipelineFlag : uint32_t {
  kIgnoreMissingVariables = 1,
  kIgnoreMissingImmutableSamplers = 2,
  kDontRemapShaderResources = 4,
  kAsynchronous = 8,
};
// GraphicsPipeline.DynamicStates (a statepack extension): the archive's dynamic-state bits
// (archive_format.hpp). Viewport, scissor, blend constants and stencil reference are always dynamic.
inline constexpr EnumEntry kDynamicStates[] = {
    {"VIEWPORT", format::kDynamicViewport},
    {"SCISSOR", format::kDynamicScissor},
    {"LINE_WIDTH", format::kDynamicLineWidth},
    {"DEPTH_BIAS", format::kDynamicDepthBias},
    {"BLEND_CONSTANTS", format::kDynamicBlendConstants},
    {"DEPTH_BOUNDS", format::kDynamicDepthBounds},
    {"STENCIL_COMPARE_MASK", format::kDynamicStencilCompareMask},
    {"STENCIL_WRITE_MASK", format::kDynamicStencilWriteMask},
    {"STENCIL_REFERENCE", format::kDynamicStencilReference},
    {"CULL_MODE", 1u << 9},
    {"FRONT_FACE", 1u << 10},
    {"PRIMITIVE_TOPOLOGY", 1u << 11},
    {"DEPTH_TEST_ENABLE", 1u << 15},
    {"DEPTH_WRITE_ENABLE", 1u << 16},
    {"DEPTH_COMPARE_OP", 1u << 17},
    {"DEPTH_BOUNDS_TEST_ENABLE", 1u << 18},
    {"STENCIL_TEST_ENABLE", 1u << 19},
    {"STENCIL_OP", 1u << 20},
    // Vulkan's, but not statepack's: viewport and scissor stay plain dynamic states, and vertex strides
    // come from the input layout.
    {"VIEWPORT_WITH_COUNT", kUnsupportedValue},
    {"SCISSOR_WITH_COUNT", kUnsupportedValue},
    {"VERTEX_INPUT_BINDING_STRIDE", kUnsupportedValue},
};

inline constexpr EnumEntry kPipelineFlags[] = {
    {"NONE", 0},
    {"IGNORE_MISSING_VARIABLES", kIgnoreMissingVariables},
    {"IGNORE_MISSING_IMMUTABLE_SAMPLERS", kIgnoreMissingImmutableSamplers},
    {"DONT_REMAP_SHADER_RESOURCES", kDontRemapShaderResources},
    {"ASYNCHRONOUS", kAsynchronous},
};

// FILTER_TYPE: the low bits are the VkFilter; comparison filters also enable comparison.
inline constexpr uint32_t kFilterComparison = 0x100;
inline constexpr uint32_t kFilterAnisotropic = 0x200;
inline constexpr EnumEntry kFilterTypes[] = {
    {"UNKNOWN", kUnsupportedValue},
    {"POINT", VK_FILTER_NEAREST},
    {"LINEAR", VK_FILTER_LINEAR},
    {"ANISOTROPIC", VK_FILTER_LINEAR | kFilterAnisotropic},
    {"COMPARISON_POINT", VK_FILTER_NEAREST | kFilterComparison},
    {"COMPARISON_LINEAR", VK_FILTER_LINEAR | kFilterComparison},
    {"COMPARISON_ANISOTROPIC", VK_FILTER_LINEAR | kFilterComparison | kFilterAnisotropic},
    {"MINIMUM_POINT", kUnsupportedValue},
    {"MINIMUM_LINEAR", kUnsupportedValue},
    {"MINIMUM_ANISOTROPIC", kUnsupportedValue},
    {"MAXIMUM_POINT", kUnsupportedValue},
    {"MAXIMUM_LINEAR", kUnsupportedValue},
    {"MAXIMUM_ANISOTROPIC", kUnsupportedValue},
};

inline constexpr EnumEntry kAddressModes[] = {
    {"UNKNOWN", kUnsupportedValue},
    {"WRAP", VK_SAMPLER_ADDRESS_MODE_REPEAT},
    {"MIRROR", VK_SAMPLER_ADDRESS_MODE_MIRRORED_REPEAT},
    {"CLAMP", VK_SAMPLER_ADDRESS_MODE_CLAMP_TO_EDGE},
    {"BORDER", VK_SAMPLER_ADDRESS_MODE_CLAMP_TO_BORDER},
    {"MIRROR_ONCE", VK_SAMPLER_ADDRESS_MODE_MIRROR_CLAMP_TO_EDGE},
};

inline constexpr EnumEntry kSamplerFlags[] = {
    {"NONE", 0}, {"SUBSAMPLED", kUnsupportedValue}, {"SUBSAMPLED_COARSE_RECONSTRUCTION", kUnsupportedValue}};

inline constexpr EnumEntry kLoadOps[] = {
    {"LOAD", VK_ATTACHMENT_LOAD_OP_LOAD},
    {"CLEAR", VK_ATTACHMENT_LOAD_OP_CLEAR},
    {"DISCARD", VK_ATTACHMENT_LOAD_OP_DONT_CARE},
};
inline constexpr EnumEntry kStoreOps[] = {
    {"STORE", VK_ATTACHMENT_STORE_OP_STORE},
    {"DISCARD", VK_ATTACHMENT_STORE_OP_DONT_CARE},
};

// RESOURCE_STATE names as image layouts (the states a render pass attachment can be in).
inline constexpr EnumEntry kResourceStates[] = {
    {"UNKNOWN", VK_IMAGE_LAYOUT_UNDEFINED},
    {"UNDEFINED", VK_IMAGE_LAYOUT_UNDEFINED},
    {"RENDER_TARGET", VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL},
    {"UNORDERED_ACCESS", VK_IMAGE_LAYOUT_GENERAL},
    {"DEPTH_WRITE", VK_IMAGE_LAYOUT_DEPTH_STENCIL_ATTACHMENT_OPTIMAL},
    {"DEPTH_READ", VK_IMAGE_LAYOUT_DEPTH_STENCIL_READ_ONLY_OPTIMAL},
    {"SHADER_RESOURCE", VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL},
    {"INPUT_ATTACHMENT", VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL},
    {"COPY_SOURCE", VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL},
    {"COPY_DEST", VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL},
    {"RESOLVE_SOURCE", VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL},
    {"RESOLVE_DEST", VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL},
    {"PRESENT", VK_IMAGE_LAYOUT_PRESENT_SRC_KHR},
    {"COMMON", VK_IMAGE_LAYOUT_GENERAL},
    {"GENERIC_READ", VK_IMAGE_LAYOUT_GENERAL},
    {"VERTEX_BUFFER", kUnsupportedValue},
    {"CONSTANT_BUFFER", kUnsupportedValue},
    {"INDEX_BUFFER", kUnsupportedValue},
    {"STREAM_OUT", kUnsupportedValue},
    {"INDIRECT_ARGUMENT", kUnsupportedValue},
    {"SHADING_RATE", kUnsupportedValue},
};

inline constexpr EnumEntry kPipelineStages[] = {
    {"UNDEFINED", 0},
    {"TOP_OF_PIPE", VK_PIPELINE_STAGE_TOP_OF_PIPE_BIT},
    {"DRAW_INDIRECT", VK_PIPELINE_STAGE_DRAW_INDIRECT_BIT},
    {"VERTEX_INPUT", VK_PIPELINE_STAGE_VERTEX_INPUT_BIT},
    {"VERTEX_SHADER", VK_PIPELINE_STAGE_VERTEX_SHADER_BIT},
    {"HULL_SHADER", VK_PIPELINE_STAGE_TESSELLATION_CONTROL_SHADER_BIT},
    {"DOMAIN_SHADER", VK_PIPELINE_STAGE_TESSELLATION_EVALUATION_SHADER_BIT},
    {"GEOMETRY_SHADER", VK_PIPELINE_STAGE_GEOMETRY_SHADER_BIT},
    {"PIXEL_SHADER", VK_PIPELINE_STAGE_FRAGMENT_SHADER_BIT},
    {"EARLY_FRAGMENT_TESTS", VK_PIPELINE_STAGE_EARLY_FRAGMENT_TESTS_BIT},
    {"LATE_FRAGMENT_TESTS", VK_PIPELINE_STAGE_LATE_FRAGMENT_TESTS_BIT},
    {"RENDER_TARGET", VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT},
    {"COMPUTE_SHADER", VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT},
    {"TRANSFER", VK_PIPELINE_STAGE_TRANSFER_BIT},
    {"BOTTOM_OF_PIPE", VK_PIPELINE_STAGE_BOTTOM_OF_PIPE_BIT},
    {"HOST", VK_PIPELINE_STAGE_HOST_BIT},
    {"ALL_GRAPHICS", VK_PIPELINE_STAGE_ALL_GRAPHICS_BIT},
    {"ALL_COMMANDS", VK_PIPELINE_STAGE_ALL_COMMANDS_BIT},
};

inline constexpr EnumEntry kAccessFlags[] = {
    {"NONE", 0},
    {"INDIRECT_COMMAND_READ", VK_ACCESS_INDIRECT_COMMAND_READ_BIT},
    {"INDEX_READ", VK_ACCESS_INDEX_READ_BIT},
    {"VERTEX_READ", VK_ACCESS_VERTEX_ATTRIBUTE_READ_BIT},
    {"UNIFORM_READ", VK_ACCESS_UNIFORM_READ_BIT},
    {"INPUT_ATTACHMENT_READ", VK_ACCESS_INPUT_ATTACHMENT_READ_BIT},
    {"SHADER_READ", VK_ACCESS_SHADER_READ_BIT},
    {"SHADER_WRITE", VK_ACCESS_SHADER_WRITE_BIT},
    {"RENDER_TARGET_READ", VK_ACCESS_COLOR_ATTACHMENT_READ_BIT},
    {"RENDER_TARGET_WRITE", VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT},
    {"DEPTH_STENCIL_READ", VK_ACCESS_DEPTH_STENCIL_ATTACHMENT_READ_BIT},
    {"DEPTH_STENCIL_WRITE", VK_ACCESS_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT},
    {"COPY_SRC", VK_ACCESS_TRANSFER_READ_BIT},
    {"COPY_DST", VK_ACCESS_TRANSFER_WRITE_BIT},
    {"HOST_READ", VK_ACCESS_HOST_READ_BIT},
    {"HOST_WRITE", VK_ACCESS_HOST_WRITE_BIT},
    {"MEMORY_READ", VK_ACCESS_MEMORY_READ_BIT},
    {"MEMORY_WRITE", VK_ACCESS_MEMORY_WRITE_BIT},
};

// VALUE_TYPE of input layout elements: bytes per component.
inline constexpr EnumEntry kValueTypes[] = {
    {"UNDEFINED", kUnsupportedValue},
    {"INT8", 1},
    {"INT16", 2},
    {"INT32", 3},
    {"UINT8", 4},
    {"UINT16", 5},
    {"UINT32", 6},
    {"FLOAT16", 7},
    {"FLOAT32", 8},
    {"FLOAT64", kUnsupportedValue},
};

inline constexpr EnumEntry kInputFrequencies[] = {{"UNDEFINED", kUnsupportedValue},
                                                  {"PER_VERTEX", VK_VERTEX_INPUT_RATE_VERTEX},
                                                  {"PER_INSTANCE", VK_VERTEX_INPUT_RATE_INSTANCE}};

// Every table above, with Diligent's name of the enum and the notation keys that take it: the
// reference in docs/notation.md is generated from this list (statepack_docs), so the documented values
// are the values the reader accepts. A table added above must be added here; a unit test counts them.
struct EnumTableInfo {
  std::string_view name;  // Diligent's enum type
  EnumTable values;
  bool bit_flags;         // one string or an array of strings, ORed (JsonReader::flags_value)
  std::string_view keys;  // where the notation takes it, comma-separated
};

inline constexpr EnumTableInfo kEnumTableInfo[] = {
    {"TEXTURE_FORMAT", kTextureFormats, false,
     "GraphicsPipeline.RTVFormats, GraphicsPipeline.DSVFormat, pAttachments[].Format"},
    {"SHADER_TYPE", kShaderTypes, false, "Desc.ShaderType"},
    {"SHADER_TYPE (stage flags)", kShaderStageFlags, true,
     "Resources[].ShaderStages, Variables[].ShaderStages, ImmutableSamplers[].ShaderStages, "
     "pSpecializationConstants[].ShaderStages, ResourceLayout.DefaultVariableMergeStages"},
    {"PIPELINE_TYPE", kPipelineTypes, false, "PSODesc.PipelineType"},
    {"SHADER_RESOURCE_VARIABLE_TYPE", kVariableTypes, false,
     "ResourceLayout.DefaultVariableType, Variables[].Type, Resources[].VarType"},
    {"SHADER_SOURCE_LANGUAGE", kSourceLanguages, false, "SourceLanguage"},
    {"SHADER_COMPILER", kShaderCompilers, false, "ShaderCompiler"},
    {"SHADER_COMPILE_FLAGS", kCompileFlags, true, "CompileFlags"},
    {"PRIMITIVE_TOPOLOGY", kTopologies, false, "GraphicsPipeline.PrimitiveTopology"},
    {"FILL_MODE", kFillModes, false, "RasterizerDesc.FillMode"},
    {"CULL_MODE", kCullModes, false, "RasterizerDesc.CullMode"},
    {"COMPARISON_FUNCTION", kComparisonFuncs, false,
     "DepthStencilDesc.DepthFunc, FrontFace/BackFace.StencilFunc, ImmutableSamplers[].Desc.ComparisonFunc"},
    {"STENCIL_OP", kStencilOps, false,
     "FrontFace/BackFace.StencilFailOp, FrontFace/BackFace.StencilDepthFailOp, "
     "FrontFace/BackFace.StencilPassOp"},
    {"BLEND_FACTOR", kBlendFactors, false,
     "RenderTargets[].SrcBlend, RenderTargets[].DestBlend, RenderTargets[].SrcBlendAlpha, "
     "RenderTargets[].DestBlendAlpha"},
    {"BLEND_OPERATION", kBlendOps, false, "RenderTargets[].BlendOp, RenderTargets[].BlendOpAlpha"},
    {"COLOR_MASK", kColorMasks, true, "RenderTargets[].RenderTargetWriteMask"},
    {"SHADER_RESOURCE_TYPE", kResourceTypes, false, "Resources[].ResourceType"},
    {"PIPELINE_RESOURCE_FLAGS", kResourceFlags, true, "Resources[].Flags"},
    {"SHADER_VARIABLE_FLAGS", kVariableFlags, true, "Variables[].Flags"},
    {"DYNAMIC_STATE (statepack)", kDynamicStates, true, "GraphicsPipeline.DynamicStates"},
    {"PSO_CREATE_FLAGS", kPipelineFlags, true, "Pipelines[].Flags"},
    {"FILTER_TYPE", kFilterTypes, false,
     "ImmutableSamplers[].Desc.MinFilter, ImmutableSamplers[].Desc.MagFilter, "
     "ImmutableSamplers[].Desc.MipFilter"},
    {"TEXTURE_ADDRESS_MODE", kAddressModes, false,
     "ImmutableSamplers[].Desc.AddressU, ImmutableSamplers[].Desc.AddressV, "
     "ImmutableSamplers[].Desc.AddressW"},
    {"SAMPLER_FLAGS", kSamplerFlags, true, "ImmutableSamplers[].Desc.Flags"},
    {"ATTACHMENT_LOAD_OP", kLoadOps, false, "pAttachments[].LoadOp, pAttachments[].StencilLoadOp"},
    {"ATTACHMENT_STORE_OP", kStoreOps, false, "pAttachments[].StoreOp, pAttachments[].StencilStoreOp"},
    {"RESOURCE_STATE", kResourceStates, false,
     "pAttachments[].InitialState, pAttachments[].FinalState, pSubpasses[] attachment references' State"},
    {"PIPELINE_STAGE_FLAGS", kPipelineStages, true,
     "pDependencies[].SrcStageMask, pDependencies[].DstStageMask"},
    {"ACCESS_FLAGS", kAccessFlags, true, "pDependencies[].SrcAccessMask, pDependencies[].DstAccessMask"},
    {"VALUE_TYPE", kValueTypes, false, "InputLayout.LayoutElements[].ValueType"},
    {"INPUT_ELEMENT_FREQUENCY", kInputFrequencies, false, "InputLayout.LayoutElements[].Frequency"},
};

}  // namespace statepack::packager
