// The notation's objects, their keys and the kind of value each key takes: one table that the reader
// checks keys against (JsonReader::check_keys) and that `statepack schema` turns into a JSON Schema
// for editors, so the two cannot drift. Enum-valued keys point at the reader's own enum tables.
#pragma once

#include <nlohmann/json.hpp>
#include <span>
#include <string_view>

#include "enum_tables.hpp"

namespace statepack::packager::schema {

enum class Kind : uint8_t {
  any,  // accepted (often "no Vulkan meaning" or refused with a reason): any JSON value
  string,
  boolean,
  unsigned_integer,  // 0 to 4294967295
  integer,           // 32-bit signed
  number,
  enumerant,       // one name of `values`
  flags,           // one name of `values`, or an array of them
  object,          // the object named `object`
  object_array,    // an array of it
  name_or_object,  // a name (of a Shaders/RenderPasses/ResourceSignatures entry) or the object
  name_or_object_array,
  index_map,  // an object keyed "0".."7" whose values are `object` objects (or enumerants)
  string_array,
  unsigned_array,
  scalar,          // a number or true/false (a specialization constant's Value)
  pipeline_array,  // Pipelines: graphics or compute pipeline objects
};

struct Property {
  std::string_view key;
  Kind kind = Kind::any;
  EnumTable values = {};         // enumerant, flags, index_map of enumerants
  std::string_view object = {};  // object kinds
};

struct ObjectSchema {
  std::string_view name;
  std::span<const Property> properties;
};

using enum Kind;

inline constexpr Property kTopLevel[] = {
    {"Imports", string_array},
    {"Defaults", object, {}, "Defaults"},
    {"Shaders", object_array, {}, "Shader"},
    {"RenderPasses", object_array, {}, "RenderPass"},
    {"ResourceSignatures", object_array, {}, "ResourceSignature"},
    {"Pipelines", pipeline_array},
    {"Ignore", object, {}, "Ignore"},
};
inline constexpr Property kIgnore[] = {{"Signatures", string_array}};
inline constexpr Property kDefaults[] = {
    {"Shader", object, {}, "Shader"},
    {"RenderPass", object, {}, "RenderPass"},
    {"ResourceSignature", object, {}, "ResourceSignature"},
    {"Pipeline", object, {}, "DefaultPipeline"},
};
inline constexpr Property kDefaultPipeline[] = {
    {"PSODesc", object, {}, "DefaultPSODesc"},
    {"Flags", flags, kPipelineFlags},
    {"ppResourceSignatures", name_or_object_array, {}, "ResourceSignature"},
    {"GraphicsPipeline", object, {}, "GraphicsPipelineDesc"},
};
inline constexpr Property kDefaultPSODesc[] = {
    {"Name", string},                             // every pipeline without one gets it, as in Diligent
    {"PipelineType", enumerant, kPipelineTypes},  // ignored with a warning, as Diligent ignores it
    {"ResourceLayout", object, {}, "ResourceLayout"},
    {"SRBAllocationGranularity", unsigned_integer},
    {"ImmediateContextMask", unsigned_integer},
};
inline constexpr Property kPSODesc[] = {
    {"Name", string},
    {"PipelineType", enumerant, kPipelineTypes},
    {"ResourceLayout", object, {}, "ResourceLayout"},
    {"SRBAllocationGranularity", unsigned_integer},
    {"ImmediateContextMask", unsigned_integer},
};
inline constexpr Property kResourceLayout[] = {
    {"DefaultVariableType", enumerant, kVariableTypes},
    {"DefaultVariableMergeStages", flags, kShaderStageFlags},
    {"Variables", object_array, {}, "Variable"},
    {"NumVariables", unsigned_integer},
    {"ImmutableSamplers", object_array, {}, "ImmutableSampler"},
    {"NumImmutableSamplers", unsigned_integer},
};
inline constexpr Property kVariable[] = {
    {"Name", string},
    {"ShaderStages", flags, kShaderStageFlags},
    {"Type", enumerant, kVariableTypes},
    {"Flags", flags, kVariableFlags},
};
inline constexpr Property kSpecializationConstant[] = {
    {"Name", string},  {"ShaderStages", flags, kShaderStageFlags},
    {"Value", scalar}, {"Size", unsigned_integer},
    {"pData", any},  // refused with the spelling that works
};
inline constexpr Property kGraphicsPipelineObject[] = {
    {"PSODesc", object, {}, "PSODesc"},
    {"Flags", flags, kPipelineFlags},
    {"ppResourceSignatures", name_or_object_array, {}, "ResourceSignature"},
    {"GraphicsPipeline", object, {}, "GraphicsPipelineDesc"},
    {"pVS", name_or_object, {}, "Shader"},
    {"pPS", name_or_object, {}, "Shader"},
    {"pDS", name_or_object, {}, "Shader"},
    {"pHS", name_or_object, {}, "Shader"},
    {"pGS", name_or_object, {}, "Shader"},
    {"pSpecializationConstants", object_array, {}, "SpecializationConstant"},
    {"NumSpecializationConstants", unsigned_integer},
};
inline constexpr Property kComputePipelineObject[] = {
    {"PSODesc", object, {}, "PSODesc"},
    {"Flags", flags, kPipelineFlags},
    {"ppResourceSignatures", name_or_object_array, {}, "ResourceSignature"},
    {"pCS", name_or_object, {}, "Shader"},
    {"pSpecializationConstants", object_array, {}, "SpecializationConstant"},
    {"NumSpecializationConstants", unsigned_integer},
};
inline constexpr Property kInputLayout[] = {
    {"LayoutElements", object_array, {}, "LayoutElement"},
    {"NumElements", unsigned_integer},
};
inline constexpr Property kLayoutElement[] = {
    {"HLSLSemantic", string},
    {"InputIndex", unsigned_integer},
    {"BufferSlot", unsigned_integer},
    {"NumComponents", unsigned_integer},
    {"ValueType", enumerant, kValueTypes},
    {"IsNormalized", boolean},
    {"RelativeOffset", unsigned_integer},
    {"Stride", unsigned_integer},
    {"Frequency", enumerant, kInputFrequencies},
    {"InstanceDataStepRate", unsigned_integer},
};
inline constexpr Property kBlendDesc[] = {
    {"AlphaToCoverageEnable", boolean},
    {"IndependentBlendEnable", boolean},
    {"RenderTargets", index_map, {}, "RenderTargetBlend"},
};
inline constexpr Property kRenderTargetBlend[] = {
    {"BlendEnable", boolean},
    {"LogicOperationEnable", boolean},
    {"SrcBlend", enumerant, kBlendFactors},
    {"DestBlend", enumerant, kBlendFactors},
    {"BlendOp", enumerant, kBlendOps},
    {"SrcBlendAlpha", enumerant, kBlendFactors},
    {"DestBlendAlpha", enumerant, kBlendFactors},
    {"BlendOpAlpha", enumerant, kBlendOps},
    {"LogicOp", any},
    {"RenderTargetWriteMask", flags, kColorMasks},
};
inline constexpr Property kShader[] = {
    {"Desc", object, {}, "ShaderDesc"},
    {"FilePath", string},
    {"Source", string},
    {"SourceLength", unsigned_integer},
    {"EntryPoint", string},
    {"Macros", object_array, {}, "Macro"},
    {"SourceLanguage", enumerant, kSourceLanguages},
    {"ShaderCompiler", enumerant, kShaderCompilers},
    {"HLSLVersion", object, {}, "ShaderVersion"},
    {"GLSLVersion", object, {}, "ShaderVersion"},
    {"GLESSLVersion", object, {}, "ShaderVersion"},
    {"MSLVersion", object, {}, "ShaderVersion"},
    {"CompileFlags", flags, kCompileFlags},
    {"ShaderOptimizationLevel", unsigned_integer},
    {"LoadConstantBufferReflection", boolean},
    {"GLSLExtensions", string},
    {"WebGPUEmulatedArrayIndexSuffix", string},
    {"ByteCode", any},  // refused: statepack compiles from source
};
inline constexpr Property kShaderDesc[] = {
    {"Name", string},
    {"ShaderType", enumerant, kShaderTypes},
    {"UseCombinedTextureSamplers", boolean},
    {"CombinedSamplerSuffix", string},
};
inline constexpr Property kMacro[] = {{"Name", string}, {"Definition", string}};
inline constexpr Property kShaderVersion[] = {{"Major", unsigned_integer}, {"Minor", unsigned_integer}};
inline constexpr Property kGraphicsPipelineDesc[] = {
    {"BlendDesc", object, {}, "BlendDesc"},
    {"SampleMask", unsigned_integer},
    {"RasterizerDesc", object, {}, "RasterizerDesc"},
    {"DepthStencilDesc", object, {}, "DepthStencilDesc"},
    {"InputLayout", object, {}, "InputLayout"},
    {"PrimitiveTopology", enumerant, kTopologies},
    {"NumViewports", unsigned_integer},
    {"NumRenderTargets", unsigned_integer},
    {"SubpassIndex", unsigned_integer},
    {"ShadingRateFlags", any},
    {"RTVFormats", index_map, kTextureFormats},
    {"DSVFormat", enumerant, kTextureFormats},
    {"ReadOnlyDSV", boolean},
    {"SmplDesc", object, {}, "SmplDesc"},
    {"NodeMask", unsigned_integer},
    {"pRenderPass", name_or_object, {}, "RenderPass"},
    {"DynamicStates", flags, kDynamicStates},
};
inline constexpr Property kRasterizerDesc[] = {
    {"FillMode", enumerant, kFillModes},
    {"CullMode", enumerant, kCullModes},
    {"FrontCounterClockwise", boolean},
    {"DepthClipEnable", boolean},
    {"ScissorEnable", boolean},
    {"AntialiasedLineEnable", boolean},
    {"DepthBias", integer},
    {"DepthBiasClamp", number},
    {"SlopeScaledDepthBias", number},
};
inline constexpr Property kDepthStencilDesc[] = {
    {"DepthEnable", boolean},
    {"DepthWriteEnable", boolean},
    {"DepthFunc", enumerant, kComparisonFuncs},
    {"StencilEnable", boolean},
    {"StencilReadMask", unsigned_integer},
    {"StencilWriteMask", unsigned_integer},
    {"FrontFace", object, {}, "StencilOpDesc"},
    {"BackFace", object, {}, "StencilOpDesc"},
};
inline constexpr Property kStencilOpDesc[] = {
    {"StencilFailOp", enumerant, kStencilOps},
    {"StencilDepthFailOp", enumerant, kStencilOps},
    {"StencilPassOp", enumerant, kStencilOps},
    {"StencilFunc", enumerant, kComparisonFuncs},
};
inline constexpr Property kSmplDesc[] = {{"Count", unsigned_integer}, {"Quality", unsigned_integer}};
inline constexpr Property kSamplerDesc[] = {
    {"Name", string},
    {"MinFilter", enumerant, kFilterTypes},
    {"MagFilter", enumerant, kFilterTypes},
    {"MipFilter", enumerant, kFilterTypes},
    {"AddressU", enumerant, kAddressModes},
    {"AddressV", enumerant, kAddressModes},
    {"AddressW", enumerant, kAddressModes},
    {"Flags", flags, kSamplerFlags},
    {"UnnormalizedCoords", boolean},
    {"MipLODBias", number},
    {"MaxAnisotropy", unsigned_integer},
    {"ComparisonFunc", enumerant, kComparisonFuncs},
    {"BorderColor", any},  // [r, g, b, a]: one of Vulkan's three core border colors
    {"MinLOD", number},
    {"MaxLOD", number},
};
inline constexpr Property kImmutableSampler[] = {
    {"ShaderStages", flags, kShaderStageFlags},
    {"SamplerOrTextureName", string},
    {"Desc", object, {}, "SamplerDesc"},
};
inline constexpr Property kResourceSignature[] = {
    {"Name", string},
    {"Resources", object_array, {}, "Resource"},
    {"NumResources", unsigned_integer},
    {"ImmutableSamplers", object_array, {}, "ImmutableSampler"},
    {"NumImmutableSamplers", unsigned_integer},
    {"BindingIndex", unsigned_integer},
    {"UseCombinedTextureSamplers", boolean},
    {"CombinedSamplerSuffix", string},
    {"SRBAllocationGranularity", unsigned_integer},
};
inline constexpr Property kResource[] = {
    {"Name", string},
    {"ShaderStages", flags, kShaderStageFlags},
    {"ArraySize", unsigned_integer},
    {"ResourceType", enumerant, kResourceTypes},
    {"VarType", enumerant, kVariableTypes},
    {"Flags", flags, kResourceFlags},
    {"WebGPUAttribs", any},
};
inline constexpr Property kRenderPass[] = {
    {"Name", string},
    {"pAttachments", object_array, {}, "Attachment"},
    {"AttachmentCount", unsigned_integer},
    {"pSubpasses", object_array, {}, "Subpass"},
    {"SubpassCount", unsigned_integer},
    {"pDependencies", object_array, {}, "Dependency"},
    {"DependencyCount", unsigned_integer},
};
inline constexpr Property kAttachment[] = {
    {"Format", enumerant, kTextureFormats},
    {"SampleCount", unsigned_integer},
    {"LoadOp", enumerant, kLoadOps},
    {"StoreOp", enumerant, kStoreOps},
    {"StencilLoadOp", enumerant, kLoadOps},
    {"StencilStoreOp", enumerant, kStoreOps},
    {"InitialState", enumerant, kResourceStates},
    {"FinalState", enumerant, kResourceStates},
};
inline constexpr Property kAttachmentReference[] = {
    {"AttachmentIndex", unsigned_integer},
    {"State", enumerant, kResourceStates},
};
inline constexpr Property kSubpass[] = {
    {"pInputAttachments", object_array, {}, "AttachmentReference"},
    {"InputAttachmentCount", unsigned_integer},
    {"pRenderTargetAttachments", object_array, {}, "AttachmentReference"},
    {"RenderTargetAttachmentCount", unsigned_integer},
    {"pResolveAttachments", object_array, {}, "AttachmentReference"},
    {"pDepthStencilAttachment", object, {}, "AttachmentReference"},
    {"pPreserveAttachments", unsigned_array},
    {"PreserveAttachmentCount", unsigned_integer},
    {"pShadingRateAttachment", any},  // refused: not supported
};
inline constexpr Property kDependency[] = {
    {"SrcSubpass", unsigned_integer},         {"DstSubpass", unsigned_integer},
    {"SrcStageMask", flags, kPipelineStages}, {"DstStageMask", flags, kPipelineStages},
    {"SrcAccessMask", flags, kAccessFlags},   {"DstAccessMask", flags, kAccessFlags},
};

// Every object, by the name properties refer to it with.
inline constexpr ObjectSchema kObjects[] = {
    {"TopLevel", kTopLevel},
    {"Ignore", kIgnore},
    {"Defaults", kDefaults},
    {"DefaultPipeline", kDefaultPipeline},
    {"DefaultPSODesc", kDefaultPSODesc},
    {"PSODesc", kPSODesc},
    {"ResourceLayout", kResourceLayout},
    {"Variable", kVariable},
    {"SpecializationConstant", kSpecializationConstant},
    {"GraphicsPipelineObject", kGraphicsPipelineObject},
    {"ComputePipelineObject", kComputePipelineObject},
    {"InputLayout", kInputLayout},
    {"LayoutElement", kLayoutElement},
    {"BlendDesc", kBlendDesc},
    {"RenderTargetBlend", kRenderTargetBlend},
    {"Shader", kShader},
    {"ShaderDesc", kShaderDesc},
    {"Macro", kMacro},
    {"ShaderVersion", kShaderVersion},
    {"GraphicsPipelineDesc", kGraphicsPipelineDesc},
    {"RasterizerDesc", kRasterizerDesc},
    {"DepthStencilDesc", kDepthStencilDesc},
    {"StencilOpDesc", kStencilOpDesc},
    {"SmplDesc", kSmplDesc},
    {"SamplerDesc", kSamplerDesc},
    {"ImmutableSampler", kImmutableSampler},
    {"ResourceSignature", kResourceSignature},
    {"Resource", kResource},
    {"RenderPass", kRenderPass},
    {"Attachment", kAttachment},
    {"AttachmentReference", kAttachmentReference},
    {"Subpass", kSubpass},
    {"Dependency", kDependency},
};

// The JSON Schema (draft-07) of a notation file.
nlohmann::json notation_json_schema();

}  // namespace statepack::packager::schema
