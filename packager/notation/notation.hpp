// The render-state notation (DRSN-compatible JSON) read into plain structs.
#pragma once

#include <cstdint>
#include <filesystem>
#include <map>
#include <memory>
#include <optional>
#include <set>
#include <string>
#include <unordered_map>
#include <utility>
#include <vector>

#include "input_file.hpp"

#include "diagnostics.hpp"
#include "format/archive_format.hpp"
#include "input_file.hpp"
#include "json_positions.hpp"

namespace statepack::packager {

// spirv: SourceLanguage BYTECODE, a SPIR-V module made by another compiler, taken as it is.
enum class SourceLanguage { glsl, hlsl, spirv };

struct ShaderDesc {
  std::string name;
  uint32_t stage = 0;  // VkShaderStageFlagBits
  SourceLanguage language = SourceLanguage::glsl;
  bool verbatim = false;       // GLSL_VERBATIM: compiled without Diligent's GLSL environment
  std::filesystem::path file;  // resolved path of FilePath, empty for inline Source
  std::string source;          // inline Source (cut to SourceLength when given)
  std::string entry_point = "main";
  std::vector<std::pair<std::string, std::string>> macros;
  // Where each Macros entry and GLSLExtensions are written (for an error glslang finds in the text they
  // put before the shader: shader_environment.hpp); macro_where may be shorter than macros.
  std::vector<Location> macro_where;
  Location extensions_where;
  uint32_t compile_flags = 0;   // CompileFlags: CompileFlag bits (enum_tables.hpp)
  std::string glsl_extensions;  // GLSLExtensions: text put after #version (GLSL)
  uint32_t glsl_version = 0;    // GLSLVersion as #version spells it (450); 0: not given
  // Desc.CombinedSamplerSuffix when Desc.UseCombinedTextureSamplers is true, else empty: an immutable
  // sampler named after a texture T then applies to the sampler T + suffix (implicit layouts).
  std::string combined_sampler_suffix;
  bool optimize = true;       // false: ShaderOptimizationLevel DISABLED (never optimised)
  bool is_reference = false;  // a pipeline slot that names a shader of the Shaders section
  bool broken = false;        // read with errors (already reported): never compiled
  Location where;

  // Same compilation input (the location does not count): identical redefinitions are allowed.
  bool same_as(const ShaderDesc& o) const {
    return name == o.name && stage == o.stage && language == o.language && verbatim == o.verbatim &&
           file == o.file && source == o.source && entry_point == o.entry_point && macros == o.macros &&
           compile_flags == o.compile_flags && glsl_extensions == o.glsl_extensions &&
           glsl_version == o.glsl_version && combined_sampler_suffix == o.combined_sampler_suffix &&
           optimize == o.optimize;
  }
};

struct ImmutableSamplerDesc {
  uint32_t stages = 0;  // VkShaderStageFlags, 0 = all
  std::string name;     // SamplerOrTextureName
  format::Sampler sampler;
  bool operator==(const ImmutableSamplerDesc&) const = default;
};

// Vulkan guarantees 128 bytes of push constants (maxPushConstantsSize): 32 values of INLINE_CONSTANTS.
inline constexpr uint32_t kGuaranteedInlineConstants = 32;

struct SignatureResource {
  std::string name;
  uint32_t stages = 0;  // VkShaderStageFlags
  uint32_t array_size = 1;
  uint32_t descriptor_type = 0;  // VkDescriptorType
  // INLINE_CONSTANTS: a CONSTANT_BUFFER of this many 32-bit values (its ArraySize), pushed rather than
  // bound; 0 for other resources. Its descriptor (array_size 1) stays in the set layout, as in Diligent.
  uint32_t inline_constants = 0;
  uint32_t var_type = 0;  // STATIC, MUTABLE, DYNAMIC: Diligent orders a signature's resources by it
  bool operator==(const SignatureResource&) const = default;
};

struct SignatureDesc {
  std::string name;
  uint32_t binding_index = 0;
  std::vector<SignatureResource> resources;
  std::vector<ImmutableSamplerDesc> immutable_samplers;
  std::string combined_sampler_suffix = "_sampler";
  Location where;
  bool broken = false;  // read with errors (already reported)
  bool same_as(const SignatureDesc& o) const {
    return name == o.name && binding_index == o.binding_index && resources == o.resources &&
           immutable_samplers == o.immutable_samplers && combined_sampler_suffix == o.combined_sampler_suffix;
  }
};

struct RenderPassDesc {
  format::RenderPass pass;  // pass.name is the name
  Location where;
  bool broken = false;  // read with errors (already reported)
  bool same_as(const RenderPassDesc& o) const { return pass == o.pass; }
};

struct ResourceVariable {
  std::string name;
  uint32_t stages = 0;            // VkShaderStageFlags; 0 = all stages of the pipeline
  std::string pointer;            // JSON pointer of the element, for errors found after compiling
  bool inline_constants = false;  // Flags INLINE_CONSTANTS: the uniform buffer becomes push constants
};

// A JSON scalar kept for later typing (a specialization constant's value is typed by the shader).
struct ScalarValue {
  enum class Kind { boolean, signed_integer, unsigned_integer, floating, other } kind = Kind::other;
  bool boolean = false;
  int64_t signed_integer = 0;
  uint64_t unsigned_integer = 0;
  double floating = 0;
  std::string text;  // as written, for messages
};

// One entry of a pipeline's pSpecializationConstants.
struct SpecConstantDesc {
  std::string name;
  uint32_t stages = 0;  // VkShaderStageFlags; 0: every stage of the pipeline whose shader declares it
  ScalarValue value;
  std::optional<uint32_t> size;  // Diligent's Size, checked against the shader's
  Location where;
};

struct PipelineDesc {
  std::string name;
  format::PipelineKind kind = format::PipelineKind::graphics;
  std::vector<ShaderDesc> shaders;  // one per stage
  format::GraphicsState graphics;
  std::vector<std::string> input_semantics;  // per graphics.vertex_attributes: its HLSLSemantic
  std::string render_pass;                   // name; empty: dynamic rendering
  uint32_t subpass = 0;                      // SubpassIndex, with a render pass only
  std::vector<std::string> signatures;       // names; empty: implicit layout
  std::vector<ResourceVariable> variables;
  std::vector<ImmutableSamplerDesc> immutable_samplers;
  std::vector<std::string> immutable_sampler_pointers;  // JSON pointer of each, for errors
  // The shaders' CombinedSamplerSuffix when they use combined samplers (set by resolve_references), else
  // empty: an immutable sampler named T then also matches the sampler T + suffix.
  std::string combined_sampler_suffix;
  uint32_t flags = 0;                                 // PipelineFlag bits
  uint32_t dynamic_states = format::kDynamicDefault;  // graphics only: the archive's bit mask
  std::vector<SpecConstantDesc> constants;
  Location where;
};

// The text of every notation file read, kept so that checks made after reading (against the compiled
// shaders) can place an error at the element it is about, looked up only when there is an error.
class SourceTexts {
 public:
  // Stores `text` for `file` (a Location's file name) and returns a view of the stored copy.
  std::string_view add(const std::string& file, std::string text);
  // The value at JSON `pointer` in the file of `object` (the location of the object it belongs to): at
  // the line and column where it is written, or its nearest written ancestor (values from Defaults).
  Location at(const Location& object, const std::string& pointer) const;
  // Every file's name and text, by name.
  std::vector<std::pair<std::string_view, std::string_view>> all() const;

 private:
  struct Source {
    std::string text;
    std::unique_ptr<JsonPositions> positions;
  };
  std::unordered_map<std::string, std::unique_ptr<Source>> by_file_;
};

// A file name the notation looked up (resolve_file) and where it was found: a notation file given or
// imported (searched in the -r directories) or a shader's FilePath (in the -s directories).
struct FileLookup {
  bool shader = false;
  std::string name;
  std::filesystem::path base_dir, found;
};

struct Notation {
  std::vector<ShaderDesc> shaders;  // the Shaders section: archived as standalone shaders
  // Shaders defined inline in pipeline slots: registered by name as in DRSN (a later pipeline may name
  // them; a different redefinition is an error), but not archived as standalone shaders.
  std::vector<ShaderDesc> inline_shaders;
  std::vector<SignatureDesc> signatures;
  std::vector<RenderPassDesc> render_passes;
  std::vector<PipelineDesc> pipelines;
  // name -> index in the lists above
  std::unordered_map<std::string, size_t> shader_index, inline_shader_index, signature_index,
      render_pass_index, pipeline_index;
  std::set<std::string> ignored_signatures;  // Ignore.Signatures
  // Imports that were not found: what they define is unknown, so an unknown name gets no suggestion.
  std::vector<std::string> failed_imports;
  std::vector<InputFile> files_read;  // every JSON file, for the depfile and output checks
  std::vector<FileLookup> lookups;    // every file name looked up, with what was found
  // Files read or being read, by identity (device and inode; the path for in-memory files): a file is
  // read once however it is imported (another spelling, `..`, a symlink, a hard link).
  std::set<std::string> files_done;
  SourceTexts sources;  // every notation file's text, for error positions
};

struct NotationOptions {
  std::vector<std::filesystem::path> render_state_dirs;  // -r
  std::vector<std::filesystem::path> shader_dirs;        // -s
  // For tests and the notation fuzzer: when set, notation files (inputs and imports) and shader files
  // are looked up in this map of path -> contents instead of on disk.
  const std::map<std::string, std::string>* memory_files = nullptr;
  uint64_t max_input_bytes = kMaxInputBytes;  // --max-input-size: each notation file at most this
};

// Reads `input` (and what it imports) and adds its objects to `notation`.
void read_notation(const std::filesystem::path& input, const NotationOptions& options, Notation& notation,
                   Diagnostics& diagnostics);

// Replaces shader references in pipelines by the named Shaders-section entries and checks that
// every named signature and render pass exists.
void resolve_references(Notation& notation, Diagnostics& diagnostics);

// The working directory, asked of the system once (statepack never changes it; asked per path, it was a
// system call per shader and #include of a pack); empty when it cannot be known.
const std::filesystem::path& working_directory();

// `path` relative to the working directory when it lies below it, else as it is: for messages.
std::string display_path(const std::filesystem::path& path);

// Finds `name` next to `base_dir` first, then in `dirs`; returns an empty path when nowhere. A regular
// file wins; failing that, anything else of that name (a directory, a FIFO) is returned, so reading it
// says what it is instead of "not found".
std::filesystem::path resolve_file(const std::string& name, const std::filesystem::path& base_dir,
                                   const std::vector<std::filesystem::path>& dirs,
                                   const std::map<std::string, std::string>* memory_files = nullptr);

}  // namespace statepack::packager
