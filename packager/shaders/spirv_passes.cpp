#include "spirv_passes.hpp"

#include <spirv-tools/optimizer.hpp>

#include "shader_compiler.hpp"

namespace statepack::packager {
namespace {

// Runs SPIRV-Tools with `register_passes`; "" or the optimizer's messages.
template <typename Register>
std::string run_passes(std::vector<uint32_t>& spirv, const CompileOptions& options,
                       Register register_passes) {
  std::string messages;
  spvtools::Optimizer optimizer(target_env(options));
  optimizer.SetMessageConsumer([&](spv_message_level_t, const char*, const spv_position_t&, const char* m) {
    messages += m;
    messages += '\n';
  });
  register_passes(optimizer);
  std::vector<uint32_t> out;
  if (!optimizer.Run(spirv.data(), spirv.size(), &out, spvtools::ValidatorOptions(), true))
    return messages.empty() ? std::string("failed") : messages;
  spirv = std::move(out);
  return "";
}

std::string strip_reflection(std::vector<uint32_t>& spirv, const CompileOptions& options) {
  if (std::string error = run_passes(
          spirv, options,
          [](spvtools::Optimizer& o) { o.RegisterPass(spvtools::CreateStripNonSemanticInfoPass()); });
      !error.empty())
    return "stripping HLSL semantics (SPIRV-Tools) failed: " + error;
  return "";
}

}  // namespace

std::string keep_entry_point(std::vector<uint32_t>& spirv, const CompileOptions& options) {
  return run_passes(spirv, options, [](spvtools::Optimizer& o) {
    o.RegisterPass(spvtools::CreateEliminateDeadFunctionsPass());
  });
}

spv_target_env target_env(const CompileOptions& options) {
  if (options.opengl) return SPV_ENV_OPENGL_4_5;
  switch (options.vulkan_version >> 12 & 0x3FF) {  // minor of VK_MAKE_API_VERSION
    case 0:
      return SPV_ENV_VULKAN_1_0;
    case 1:
      return SPV_ENV_VULKAN_1_1;
    case 2:
      return SPV_ENV_VULKAN_1_2;
    default:
      return SPV_ENV_VULKAN_1_3;
  }
}

std::string legalize_hlsl(std::vector<uint32_t>& spirv, const CompileOptions& options, bool vertex,
                          std::vector<VertexInputSemantic>& semantics) {
  if (std::string error =
          run_passes(spirv, options, [](spvtools::Optimizer& o) { o.RegisterLegalizationPasses(); });
      !error.empty())
    return "HLSL legalization (SPIRV-Tools) failed: " + error;
  return prepare_module(spirv, options, false, vertex, semantics);
}

uint32_t max_spirv_version(const CompileOptions& options) {
  if (options.opengl) return 0x00010000;
  switch (options.vulkan_version >> 12 & 0x3FF) {
    case 0:
      return 0x00010000;
    case 1:
      return 0x00010300;
    case 2:
      return 0x00010500;
    default:
      return 0x00010600;
  }
}

std::string prepare_module(std::vector<uint32_t>& spirv, const CompileOptions& options, bool hlsl,
                           bool vertex, std::vector<VertexInputSemantic>& semantics) {
  if (hlsl) return legalize_hlsl(spirv, options, vertex, semantics);  // (which comes back with hlsl false)
  if (vertex) {
    semantics = vertex_input_semantics(spirv);
    if (std::string error = place_attrib_inputs(spirv, semantics); !error.empty()) return error;
  }
  return strip_reflection(spirv, options);
}

std::string remove_unused_globals(std::vector<uint32_t>& spirv, const CompileOptions& options) {
  const uint32_t vulkan_version = options.opengl ? 0x00400000u : options.vulkan_version;  // GL: SPIR-V 1.0
  std::string messages;
  spvtools::Optimizer optimizer(target_env(options));
  optimizer.SetMessageConsumer([&](spv_message_level_t, const char*, const spv_position_t&, const char* m) {
    messages += m;
    messages += '\n';
  });
  // Before SPIR-V 1.4 an entry point's interface lists only its inputs and outputs, so dead-variable
  // elimination removes unused resources and keeps every declared input and output (an input a stage
  // declares but does not read still matches the previous stage's output). From 1.4 on every global is
  // in the interface, so unused ones must first leave it.
  const uint32_t minor = vulkan_version >> 12 & 0x3FF;
  if (minor >= 2) optimizer.RegisterPass(spvtools::CreateRemoveUnusedInterfaceVariablesPass());
  optimizer.RegisterPass(spvtools::CreateDeadVariableEliminationPass());
  std::vector<uint32_t> out;
  // No validation here: the finalised module is validated once, with the layout applied.
  if (!optimizer.Run(spirv.data(), spirv.size(), &out, spvtools::ValidatorOptions(), true))
    return "removing unused globals failed: " + messages;
  spirv = std::move(out);
  return "";
}

}  // namespace statepack::packager
