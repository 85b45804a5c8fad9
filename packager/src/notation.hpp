// The render-state notation (DRSN-compatible JSON) read into plain structs.
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <utility>
#include <vector>

#include "diagnostics.hpp"
#include "statepack/archive_format.hpp"

namespace statepack::packager {

enum class SourceLanguage { glsl, hlsl };

struct ShaderDesc {
  std::string name;
  uint32_t stage = 0;  // VkShaderStageFlagBits
  SourceLanguage language = SourceLanguage::glsl;
  std::filesystem::path file;  // resolved path of FilePath, empty for inline Source
  std::string file_display;    // FilePath as written, for messages
  std::string source;          // inline Source
  std::string entry_point = "main";
  std::vector<std::pair<std::string, std::string>> macros;
  bool is_reference = false;  // a pipeline slot that names a shader of the Shaders section
  Location where;
};

struct ResourceVariable {
  std::string name;
  uint32_t stages = 0;  // VkShaderStageFlags; 0 = all stages of the pipeline
  std::string type;     // STATIC / MUTABLE / DYNAMIC (kept for reflection; Vulkan needs no difference)
};

struct PipelineDesc {
  std::string name;
  format::PipelineKind kind = format::PipelineKind::graphics;
  std::vector<ShaderDesc> shaders;  // one per stage
  format::GraphicsState graphics;
  std::vector<ResourceVariable> variables;
  Location where;
};

struct Notation {
  std::vector<ShaderDesc> shaders;  // the Shaders section (standalone)
  std::vector<PipelineDesc> pipelines;
  std::vector<std::filesystem::path> files_read;  // every JSON file, for the depfile
};

struct NotationOptions {
  std::vector<std::filesystem::path> render_state_dirs;  // -r
  std::vector<std::filesystem::path> shader_dirs;        // -s
};

// Reads `input` and adds its objects to `notation`; problems go to `diagnostics`.
void read_notation(const std::filesystem::path& input, const NotationOptions& options, Notation& notation,
                   Diagnostics& diagnostics);

// Replaces shader references in pipelines by the named Shaders-section entries.
void resolve_references(Notation& notation, Diagnostics& diagnostics);

// `path` relative to the working directory when it lies below it, else as it is: for messages.
std::string display_path(const std::filesystem::path& path);

// Finds `name` next to `base_dir` first, then in `dirs`; returns an empty path when nowhere.
std::filesystem::path resolve_file(const std::string& name, const std::filesystem::path& base_dir,
                                   const std::vector<std::filesystem::path>& dirs);

}  // namespace statepack::packager
