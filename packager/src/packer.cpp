#include "packer.hpp"

#include <unistd.h>
#include <vulkan/vulkan_core.h>

#include <algorithm>
#include <atomic>
#include <cstdio>
#include <deque>
#include <fstream>
#include <map>
#include <ostream>
#include <set>
#include <thread>

#include "spirv_reflect.hpp"
#include "statepack/archive_format.hpp"
#include "suggest.hpp"

namespace statepack::packager {
namespace fs = std::filesystem;
namespace {

constexpr uint32_t kProducerVersion = (0u << 22) | (1u << 12) | 0u;  // 0.1.0

// Two pipeline slots compile to the same module when everything that feeds glslang is equal.
std::string compile_key(const ShaderDesc& s) {
  std::string key = std::to_string(s.stage) + '\0' + std::to_string(int(s.language)) + '\0' + s.entry_point +
                    '\0' + s.file.string() + '\0' + s.source;
  for (const auto& [name, value] : s.macros) key += '\0' + name + '=' + value;
  return key;
}

struct CompiledUnit {
  ShaderDesc desc;
  CompiledShader compiled;
  Reflection reflection;
};

// Compiles every distinct shader once, on `threads` threads.
void compile_all(std::vector<CompiledUnit>& units, const CompileOptions& options, uint32_t threads,
                 Diagnostics& diag) {
  std::atomic<size_t> next{0};
  auto worker = [&] {
    for (size_t i = next++; i < units.size(); i = next++) {
      units[i].compiled = compile_shader(units[i].desc, options, diag);
      if (units[i].compiled.ok) {
        units[i].reflection = reflect_spirv(units[i].compiled.spirv);
        if (!units[i].reflection.error.empty())
          diag.error(units[i].desc.where, "shader '" + units[i].desc.name +
                                              "': SPIR-V reflection failed: " + units[i].reflection.error);
      }
    }
  };
  uint32_t n = threads ? threads : std::max(1u, std::thread::hardware_concurrency());
  n = std::min<uint32_t>(n, static_cast<uint32_t>(std::max<size_t>(units.size(), 1)));
  std::vector<std::thread> pool;
  for (uint32_t i = 1; i < n; ++i) pool.emplace_back(worker);
  worker();
  for (auto& t : pool) t.join();
}

const char* stage_name(uint32_t stage) {
  switch (stage) {
    case VK_SHADER_STAGE_VERTEX_BIT:
      return "vertex";
    case VK_SHADER_STAGE_FRAGMENT_BIT:
      return "pixel";
    case VK_SHADER_STAGE_COMPUTE_BIT:
      return "compute";
    case VK_SHADER_STAGE_GEOMETRY_BIT:
      return "geometry";
    case VK_SHADER_STAGE_TESSELLATION_CONTROL_BIT:
      return "hull";
    case VK_SHADER_STAGE_TESSELLATION_EVALUATION_BIT:
      return "domain";
  }
  return "unknown";
}

class ContentsBuilder {
 public:
  uint32_t add_blob(const std::vector<uint32_t>& words) {
    auto bytes = std::as_bytes(std::span(words));
    uint64_t hash = format::hash_bytes({reinterpret_cast<const uint8_t*>(bytes.data()), bytes.size()});
    for (auto [it, end] = blob_by_hash_.equal_range(hash); it != end; ++it)
      if (std::ranges::equal(contents.spirv[it->second], words)) return it->second;  // hash + byte compare
    blobs_.push_back(words);
    contents.spirv.emplace_back(blobs_.back());
    uint32_t index = static_cast<uint32_t>(contents.spirv.size() - 1);
    blob_by_hash_.emplace(hash, index);
    return index;
  }
  uint32_t add_shader(format::Shader shader) {
    for (uint32_t i = 0; i < contents.shaders.size(); ++i) {
      const auto& s = contents.shaders[i];
      if (s.name == shader.name && s.stage == shader.stage && s.blob == shader.blob &&
          s.entry_point == shader.entry_point)
        return i;
    }
    contents.shaders.push_back(std::move(shader));
    return static_cast<uint32_t>(contents.shaders.size() - 1);
  }
  uint32_t add_set_layout(format::SetLayout layout) {
    for (uint32_t i = 0; i < contents.set_layouts.size(); ++i) {
      const auto& l = contents.set_layouts[i].bindings;
      if (std::ranges::equal(l, layout.bindings, [](const format::Binding& a, const format::Binding& b) {
            return a.name == b.name && a.binding == b.binding && a.descriptor_type == b.descriptor_type &&
                   a.count == b.count && a.stage_flags == b.stage_flags;
          }))
        return i;
    }
    contents.set_layouts.push_back(std::move(layout));
    return static_cast<uint32_t>(contents.set_layouts.size() - 1);
  }

  format::Contents contents;

 private:
  std::deque<std::vector<uint32_t>> blobs_;  // stable storage behind contents.spirv
  std::multimap<uint64_t, uint32_t> blob_by_hash_;
};

// Merges the shaders' reflected resources into the pipeline's set layouts; checks agreement.
bool build_layout(const PipelineDesc& p, const std::vector<const CompiledUnit*>& units,
                  ContentsBuilder& builder, format::Pipeline& out, Diagnostics& diag) {
  std::map<std::pair<uint32_t, uint32_t>, format::Binding> merged;  // (set, binding)
  std::map<std::pair<uint32_t, uint32_t>, std::string> first_shader;
  bool ok = true;
  for (const CompiledUnit* unit : units) {
    for (const ReflectedBinding& r : unit->reflection.bindings) {
      if (r.count == 0) {
        diag.error(p.where, "pipeline '" + p.name + "', shader '" + unit->desc.name + "': resource '" +
                                r.name + "' is a runtime-sized array, which is not supported yet");
        ok = false;
        continue;
      }
      auto key = std::pair{r.set, r.binding};
      auto [it, inserted] =
          merged.try_emplace(key, format::Binding{r.name, r.binding, r.descriptor_type, r.count, 0});
      if (!inserted && (it->second.descriptor_type != r.descriptor_type || it->second.count != r.count)) {
        diag.error(p.where, "pipeline '" + p.name + "': resource '" + r.name + "' (set " +
                                std::to_string(r.set) + ", binding " + std::to_string(r.binding) +
                                ") has another type or array size in shader '" + unit->desc.name +
                                "' than in shader '" + first_shader[key] + "'");
        ok = false;
        continue;
      }
      if (inserted) first_shader[key] = unit->desc.name;
      it->second.stage_flags |= unit->desc.stage;
    }
    out.push_constant_size = std::max(out.push_constant_size, unit->reflection.push_constant_size);
    if (unit->reflection.push_constant_size > 0) out.push_constant_stages |= unit->desc.stage;
  }
  // Every ResourceLayout variable must name a resource of the pipeline's shaders, in the stages given.
  for (const ResourceVariable& v : p.variables) {
    std::vector<std::string> names;
    bool found = false;
    for (const auto& [key, b] : merged) {
      names.push_back(b.name);
      if (b.name != v.name) continue;
      found = true;
      if (v.stages != 0 && (b.stage_flags & v.stages) == 0) {
        diag.error(p.where, "pipeline '" + p.name + "': variable '" + v.name +
                                "' is declared for stages its shaders do not use it in");
        ok = false;
      }
    }
    if (!found) {
      diag.error(p.where, "pipeline '" + p.name + "': ResourceLayout variable '" + v.name +
                              "' is not used by any of its shaders" + did_you_mean(v.name, names));
      ok = false;
    }
  }
  uint32_t set_count = 0;
  for (const auto& [key, b] : merged) set_count = std::max(set_count, key.first + 1);
  for (uint32_t set = 0; set < set_count; ++set) {
    format::SetLayout layout;
    for (const auto& [key, b] : merged)
      if (key.first == set) layout.bindings.push_back(b);  // map order: sorted by binding
    out.set_layouts.push_back(layout.bindings.empty() ? format::kNone
                                                      : builder.add_set_layout(std::move(layout)));
  }
  return ok;
}

std::string depfile_escape(const std::string& path) {
  std::string out;
  for (char c : path) {
    if (c == ' ' || c == '#') out += '\\';
    if (c == '$') out += '$';
    out += c;
  }
  return out;
}

void print_contents(const format::Contents& c, size_t archive_size, std::ostream& out) {
  out << "Archive: " << archive_size << " bytes, format v" << format::kFormatVersion << ", content version "
      << c.content_version << ", backends: vulkan\n";
  out << "Pipelines (" << c.pipelines.size() << "):\n";
  std::vector<const format::Pipeline*> sorted;
  for (const auto& p : c.pipelines) sorted.push_back(&p);
  std::ranges::sort(sorted, [](auto* a, auto* b) { return a->name < b->name; });
  for (const auto* p : sorted) {
    out << "  '" << p->name << "' (" << (p->kind == format::PipelineKind::compute ? "compute" : "graphics")
        << ")\n";
    for (uint32_t s : p->shaders) {
      const auto& shader = c.shaders[s];
      out << "    " << stage_name(shader.stage) << " '" << shader.name
          << "': " << c.spirv[shader.blob].size_bytes() << " bytes SPIR-V\n";
    }
    for (uint32_t set = 0; set < p->set_layouts.size(); ++set) {
      if (p->set_layouts[set] == format::kNone) continue;
      for (const auto& b : c.set_layouts[p->set_layouts[set]].bindings)
        out << "    set " << set << " binding " << b.binding << ": '" << b.name << "' (descriptor type "
            << b.descriptor_type << ", count " << b.count << ")\n";
    }
  }
  size_t spirv_bytes = 0;
  for (auto blob : c.spirv) spirv_bytes += blob.size_bytes();
  out << "SPIR-V blobs: " << c.spirv.size() << " unique, " << spirv_bytes << " bytes\n";
}

}  // namespace

bool write_file_atomically(const fs::path& path, const std::string& bytes, std::string& error) {
  fs::path temp = path;
  temp += ".tmp-" + std::to_string(::getpid());
  {
    std::ofstream file(temp, std::ios::binary | std::ios::trunc);
    if (!file) {
      error = "cannot create '" + temp.string() + "'";
      return false;
    }
    file.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
    file.flush();
    if (!file) {
      error = "cannot write '" + temp.string() + "'";
      std::error_code ec;
      fs::remove(temp, ec);
      return false;
    }
  }
  std::error_code ec;
  fs::rename(temp, path, ec);
  if (ec) {
    error = "cannot rename '" + temp.string() + "' to '" + path.string() + "': " + ec.message();
    fs::remove(temp, ec);
    return false;
  }
  return true;
}

int run_pack(const PackOptions& options, std::ostream& out, std::ostream& err) {
  Diagnostics diag;
  Notation notation;
  for (const auto& input : options.inputs) read_notation(input, options.notation, notation, diag);
  resolve_references(notation, diag);
  if (notation.pipelines.empty() && !diag.has_errors())
    diag.error({options.inputs.empty() ? "" : options.inputs.front().string()}, "no pipelines to pack");

  // Distinct shaders, each compiled once.
  std::vector<CompiledUnit> units;
  std::map<std::string, size_t> unit_by_key;
  auto unit_for = [&](const ShaderDesc& s) {
    auto [it, inserted] = unit_by_key.try_emplace(compile_key(s), units.size());
    if (inserted) units.push_back({s, {}, {}});
    return it->second;
  };
  std::vector<std::vector<size_t>> pipeline_units;
  for (const auto& p : notation.pipelines) {
    pipeline_units.emplace_back();
    for (const auto& s : p.shaders)
      if (!s.is_reference) pipeline_units.back().push_back(unit_for(s));
  }
  for (const auto& s : notation.shaders) unit_for(s);  // standalone shaders are checked too
  if (!diag.has_errors()) compile_all(units, options.compile, options.threads, diag);

  ContentsBuilder builder;
  builder.contents.producer_version = kProducerVersion;
  builder.contents.content_version = options.content_version;
  builder.contents.backends = format::kBackendVulkan;
  if (!diag.has_errors()) {
    for (size_t i = 0; i < notation.pipelines.size(); ++i) {
      const PipelineDesc& p = notation.pipelines[i];
      format::Pipeline out_pipeline;
      out_pipeline.name = p.name;
      out_pipeline.kind = p.kind;
      out_pipeline.graphics = p.graphics;
      std::vector<const CompiledUnit*> used;
      for (size_t u : pipeline_units[i]) {
        const CompiledUnit& unit = units[u];
        used.push_back(&unit);
        uint32_t blob = builder.add_blob(unit.compiled.spirv);
        out_pipeline.shaders.push_back(
            builder.add_shader({unit.desc.name, unit.desc.stage, blob, unit.desc.entry_point}));
      }
      if (build_layout(p, used, builder, out_pipeline, diag))
        builder.contents.pipelines.push_back(std::move(out_pipeline));
    }
  }
  if (diag.has_errors()) {
    diag.print(err);
    err << "statepack: " << diag.error_count() << " error(s); no archive written\n";
    return kExitInputError;
  }
  diag.print(err);  // warnings

  std::vector<uint8_t> bytes = format::encode(builder.contents);
  std::string error;
  if (!write_file_atomically(options.output, std::string(bytes.begin(), bytes.end()), error)) {
    err << "statepack: error: " << error << '\n';
    return kExitIoError;
  }
  if (options.depfile) {
    // Make syntax: "<output>: <every JSON and shader file read>", one dependency per line.
    std::set<std::string> deps;
    for (const auto& f : notation.files_read) deps.insert(f.string());
    for (const auto& u : units)
      for (const auto& f : u.compiled.files_read) deps.insert(f.string());
    std::string text = depfile_escape(options.output.string()) + ":";
    for (const auto& d : deps) text += " \\\n  " + depfile_escape(d);
    text += "\n";
    if (!write_file_atomically(*options.depfile, text, error)) {
      err << "statepack: error: " << error << '\n';
      return kExitIoError;
    }
  }
  if (options.print_contents) print_contents(builder.contents, bytes.size(), out);
  return kExitSuccess;
}

}  // namespace statepack::packager
