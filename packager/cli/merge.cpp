#include "merge.hpp"

#include <map>
#include <ostream>
#include <string>

#include "format/archive_file.hpp"
#include "layout/contents_builder.hpp"
#include "notation/diagnostics.hpp"
#include "pack/packer.hpp"
#include "support/file_io.hpp"
#include "support/output_files.hpp"
#include "version.hpp"

namespace statepack::packager {
namespace fs = std::filesystem;
namespace {

// Adds one decoded archive to the merged contents, remapping every index into the builder's.
class Merger {
 public:
  // Returns an error message, or empty.
  std::string add(const format::Contents& c, const std::string& file) {
    std::vector<uint32_t> blobs, shaders, samplers, layouts, passes;
    for (auto blob : c.spirv) blobs.push_back(builder_.add_blob({blob.begin(), blob.end()}));
    for (format::Shader s : c.shaders) {
      s.blob = blobs[s.blob];
      shaders.push_back(builder_.add_shader(s));
    }
    for (const format::Sampler& s : c.samplers) samplers.push_back(builder_.add_sampler(s));
    for (format::SetLayout l : c.set_layouts) {
      for (format::Binding& b : l.bindings)
        if (b.immutable_sampler != format::kNone) b.immutable_sampler = samplers[b.immutable_sampler];
      // A signature's layout is unpackable by name, so one name must mean one layout.
      if (!l.name.empty())
        if (std::string e = claim("resource signature", l.name, file, format::record_key(l)); !e.empty())
          return e;
      layouts.push_back(builder_.add_set_layout(l));
    }
    for (const format::RenderPass& r : c.render_passes) {
      if (std::string e = claim("render pass", r.name, file, format::record_key(r)); !e.empty()) return e;
      passes.push_back(builder_.add_render_pass(r));
    }
    for (uint32_t s : c.standalone_shaders) {
      const format::Shader& shader = builder_.contents.shaders[shaders[s]];
      if (std::string e = claim("shader", shader.name, file, std::to_string(shaders[s])); !e.empty())
        return e;
      if (standalone_.insert(shaders[s]).second) builder_.contents.standalone_shaders.push_back(shaders[s]);
    }
    for (format::Pipeline p : c.pipelines) {
      for (uint32_t& s : p.shaders) s = shaders[s];
      for (uint32_t& l : p.set_layouts)
        if (l != format::kNone) l = layouts[l];
      if (p.kind == format::PipelineKind::graphics && p.render_pass != format::kNone)
        p.render_pass = passes[p.render_pass];
      auto [it, inserted] = pipelines_.try_emplace(p.name, builder_.contents.pipelines.size(), file);
      if (inserted) {
        builder_.contents.pipelines.push_back(std::move(p));
      } else if (!(builder_.contents.pipelines[it->second.first] == p)) {
        return "pipeline '" + p.name + "' is defined differently in '" + it->second.second + "' and '" +
               file + "'";
      }
    }
    // The OpenGL block: its shaders point at blobs, like the Vulkan part's; one name, one definition.
    for (format::GlPipeline p : c.gl_pipelines) {
      for (format::GlShader& s : p.shaders) s.blob = blobs[s.blob];
      auto [it, inserted] = gl_pipelines_.try_emplace(p.name, builder_.contents.gl_pipelines.size(), file);
      if (inserted) {
        builder_.contents.gl_pipelines.push_back(std::move(p));
      } else if (!(builder_.contents.gl_pipelines[it->second.first] == p)) {
        return "OpenGL pipeline '" + p.name + "' is defined differently in '" + it->second.second +
               "' and '" + file + "'";
      }
    }
    builder_.contents.backends |= c.backends;
    return {};
  }

  format::Contents& contents() { return builder_.contents; }

 private:
  // Records that `file` defines `kind` `name` as `key`; a second, different definition is an error.
  std::string claim(const char* kind, const std::string& name, const std::string& file, std::string key) {
    auto [it, inserted] = named_.try_emplace(std::string(kind) + '\0' + name, std::move(key), file);
    if (inserted || it->second.first == key) return {};
    return std::string(kind) + " '" + name + "' is defined differently in '" + it->second.second + "' and '" +
           file + "'";
  }
  ContentsBuilder builder_;
  std::map<std::string, std::pair<std::string, std::string>> named_;  // kind+name -> key, file
  std::map<std::string, std::pair<size_t, std::string>> pipelines_;   // name -> index, file
  std::map<std::string, std::pair<size_t, std::string>> gl_pipelines_;
  std::set<uint32_t> standalone_;
};

}  // namespace

int run_merge(const MergeOptions& options, std::ostream& out, std::ostream& err) {
  // The output is refused before any work when it cannot be written or is one of the inputs.
  std::vector<InputFile> inputs;
  for (const fs::path& path : options.inputs)
    if (auto identity = detail::file_identity(path)) inputs.push_back({path, *identity});
  detail::OutputSet outputs(inputs);
  if (std::string reason = outputs.refuse_reason(options.output); !reason.empty()) {
    err << "statepack: error: " << printable(reason) << '\n';
    return kExitUsage;
  }
  std::vector<format::LoadedArchive> archives;  // kept: the merged contents point into their SPIR-V
  std::optional<uint32_t> content_version = options.content_version;
  Merger merger;
  for (const fs::path& path : options.inputs) {
    const std::string file = printable(path.string());
    auto archive = format::load_archive_file_with_opengl(path);
    if (!archive) {
      err << "statepack: error: " << printable(archive.error().message) << '\n';
      return kExitInputError;
    }
    const format::Contents& c = archive->contents;
    if (!options.content_version) {
      if (content_version && *content_version != c.content_version) {
        err << "statepack: error: '" << file << "' has content version " << c.content_version
            << ", the archives before it " << *content_version << ": give the merged one with -v\n";
        return kExitInputError;
      }
      content_version = c.content_version;
    }
    if (std::string problem = merger.add(c, file); !problem.empty()) {
      err << "statepack: error: " << printable(problem) << '\n';
      return kExitInputError;
    }
    archives.push_back(std::move(*archive));
  }
  format::Contents& merged = merger.contents();
  merged.producer_version = kProducerVersion;
  merged.content_version = content_version.value_or(0);
  std::vector<uint8_t> bytes = format::encode(merged);
  Result<void> written = outputs.stage(options.output, bytes);
  if (written) written = outputs.commit();
  if (!written) {
    err << "statepack: error: " << printable(written.error().message) << '\n';
    return exit_code_of_output_error(written.error());
  }
  out << "statepack: merged " << options.inputs.size() << " archive(s) into '"
      << printable(options.output.string()) << "': " << merged.pipelines.size() << " pipeline(s), "
      << merged.spirv.size() << " SPIR-V blob(s), " << bytes.size() << " bytes\n";
  return kExitSuccess;
}

}  // namespace statepack::packager
