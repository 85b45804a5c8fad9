// Readers for the notation's objects: shaders, graphics state, samplers, resource signatures and
// render passes. Each reports every problem through the JsonReader and returns nothing on error.
#pragma once

#include <filesystem>
#include <map>
#include <optional>

#include "json_reader.hpp"
#include "notation.hpp"

namespace statepack::packager {

// Defaults mode reads a Defaults block: required fields may be missing.
struct ReadContext {
  JsonReader& json;
  std::filesystem::path base_dir;  // the notation file's directory
  const NotationOptions& options;
  bool defaults_mode = false;
  // FilePath values already found from this file: thousands of pipelines naming one shader file look
  // it up once, not once each.
  std::map<std::string, std::filesystem::path, std::less<>> resolved_files;
};

// `slot_stage`: the stage a pipeline slot requires (0 for the Shaders section).
std::optional<ShaderDesc> read_shader(ReadContext& ctx, const Json& j, const std::string& pointer,
                                      uint32_t slot_stage);

// The GraphicsPipeline object, except pRenderPass, which the pipeline reader resolves. `semantics`:
// each InputLayout element's HLSLSemantic (Diligent's default "ATTRIB"), beside g.vertex_attributes.
void read_graphics_state(ReadContext& ctx, const Json& j, const std::string& pointer,
                         format::GraphicsState& g, uint32_t& subpass, std::vector<std::string>& semantics);

std::optional<format::Sampler> read_sampler(ReadContext& ctx, const Json& j, const std::string& pointer);
std::vector<ImmutableSamplerDesc> read_immutable_samplers(ReadContext& ctx, const Json& j,
                                                          const std::string& pointer);

std::optional<SignatureDesc> read_signature(ReadContext& ctx, const Json& j, const std::string& pointer);
std::optional<RenderPassDesc> read_render_pass(ReadContext& ctx, const Json& j, const std::string& pointer);

}  // namespace statepack::packager
