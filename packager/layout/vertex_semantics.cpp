#include "vertex_semantics.hpp"

#include <algorithm>
#include <cctype>
#include <map>

namespace statepack::packager {
namespace {

bool is_attrib(const std::string& semantic) {
  std::string upper = semantic;
  for (char& c : upper) c = char(std::toupper(static_cast<unsigned char>(c)));
  return upper == "ATTRIB";
}

std::string input_text(const InterfaceVariable& v, const std::string& semantic) {
  return "'" + v.name + "' (" + semantic + ", location " + std::to_string(v.location) + ")";
}

}  // namespace

bool place_inputs_by_semantic(const PipelineDesc& p, const StageInput& vs, std::vector<uint32_t>& spirv,
                              Reflection& reflection, const SourceTexts& sources, Diagnostics& diag) {
  if (!vs.semantics) return true;
  const auto& attributes = p.graphics.vertex_attributes;
  const std::string layout = p.where.pointer + "/GraphicsPipeline/InputLayout";
  std::map<uint32_t, const InterfaceVariable*> input_of;  // variable id -> its reflected input
  for (const InterfaceVariable& v : reflection.inputs) input_of.emplace(v.variable, &v);
  std::map<uint32_t, std::string> semantic_of;
  for (const VertexInputSemantic& s : *vs.semantics)
    if (input_of.count(s.variable)) semantic_of[s.variable] = s.semantic;

  std::map<uint32_t, uint32_t> moves;  // variable id -> its location in this pipeline
  for (size_t i = 0; i < attributes.size() && i < p.input_semantics.size(); ++i) {
    const std::string& name = p.input_semantics[i];
    if (is_attrib(name)) continue;  // placed by the compiler already
    const uint32_t index = attributes[i].location;
    auto match = std::find_if(semantic_of.begin(), semantic_of.end(),
                              [&](const auto& s) { return semantic_matches(s.second, name, index); });
    if (match == semantic_of.end()) {
      std::string have;
      for (const auto& [id, semantic] : semantic_of) have += (have.empty() ? "" : ", ") + semantic;
      diag.warning(sources.at(p.where, layout + "/LayoutElements/" + std::to_string(i)),
                   "pipeline '" + p.name + "': InputLayout element " + std::to_string(i) + " (HLSLSemantic " +
                       name + ", InputIndex " + std::to_string(index) +
                       ") names no input of vertex shader '" + vs.desc->name +
                       "' (its inputs' semantics: " + (have.empty() ? "none" : have) + ")");
      continue;
    }
    moves[match->first] = index;
  }
  // Inputs no ATTRIBn and no element place keep where glslang put them: say so, once per pipeline.
  if (!attributes.empty()) {
    std::string unplaced;
    for (const auto& [id, semantic] : semantic_of)
      if (!attrib_index(semantic) && !moves.count(id))
        unplaced += (unplaced.empty() ? "" : ", ") + input_text(*input_of[id], semantic);
    if (!unplaced.empty())
      diag.warning(vs.desc->where,
                   "pipeline '" + p.name + "': vertex shader '" + vs.desc->name + "' reads " + unplaced +
                       ": not ATTRIBn, and no InputLayout element names its semantic (HLSLSemantic), so it "
                       "reads the location glslang gave it (the order of declaration), as in Diligent's "
                       "Vulkan backend; name it ATTRIBn for location n, or give its element HLSLSemantic");
  }
  if (moves.empty()) return true;

  for (const auto& [id, location] : moves) set_location(spirv, id, location);
  for (InterfaceVariable& v : reflection.inputs)
    if (auto it = moves.find(v.variable); it != moves.end()) v.location = it->second;
  std::map<uint32_t, const InterfaceVariable*> owner;
  for (const InterfaceVariable& v : reflection.inputs) {
    const uint32_t count = std::min<uint32_t>(v.array_size * v.locations_per_element(), 64);
    for (uint32_t l = v.location; l < v.location + count; ++l) {
      auto [it, inserted] = owner.emplace(l, &v);
      if (inserted || it->second->variable == v.variable) continue;
      diag.error(sources.at(p.where, layout),
                 "pipeline '" + p.name + "': vertex shader '" + vs.desc->name + "' inputs " +
                     input_text(*it->second, semantic_of[it->second->variable]) + " and " +
                     input_text(v, semantic_of[v.variable]) + " both read location " + std::to_string(l) +
                     " once InputLayout's HLSLSemantic names are matched (an input of semantic ATTRIBn reads "
                     "location n)");
      return false;
    }
  }
  return true;
}

}  // namespace statepack::packager
