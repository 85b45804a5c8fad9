#include "packer.hpp"

#include <vulkan/vulkan_core.h>

#include <algorithm>
#include <atomic>
#include <bit>
#include <chrono>
#include <functional>
#include <map>
#include <mutex>
#include <ostream>
#include <set>
#include <thread>

#include "cli/inspect.hpp"
#include "format/archive_file.hpp"
#include "format/archive_format.hpp"
#include "format/spirv_walk.hpp"
#include "layout/contents_builder.hpp"
#include "layout/gl_layout.hpp"
#include "layout/interface_check.hpp"
#include "layout/pipeline_layout.hpp"
#include "layout/specialization.hpp"
#include "layout/vertex_semantics.hpp"
#include "notation/input_file.hpp"
#include "pack/archive_reuse.hpp"
#include "pack/compiler_warmup.hpp"
#include "pack/input_stamps.hpp"
#include "pack/phase_times.hpp"
#include "pack/repack_memo.hpp"
#include "shaders/compile_cache.hpp"
#include "shaders/gl_translate.hpp"
#include "shaders/nesting_bound.hpp"
#include "shaders/spirv_reflect.hpp"
#include "version.hpp"

namespace statepack::packager {
namespace fs = std::filesystem;
namespace {

constexpr size_t kNoJob = SIZE_MAX;

struct CompiledUnit {
  ShaderDesc desc;
  CompiledShader compiled;
  Reflection reflection;
  std::optional<spirv::Module> module;           // the compiled SPIR-V walked, for the layout's checks
  bool in_shard = false;                         // --shard: this unit's compile key falls in the pack's shard
  bool compiled_here = false;                    // not found in a cache: compiled by this pack
  std::shared_ptr<const RepackMemo::Unit> held;  // what a --watch session's memory gave (repack_memo.hpp)
};

// A path in a depfile, written so that Make and Ninja both read it back as the path (tried with GNU
// Make 4.3 and Ninja 1.11): ' ' and '#' get a backslash (backslashes before them doubled), ':' a
// backslash, '$' doubles. A path that has no such spelling is refused, and `refused` says by what: a
// control character (a newline cannot be escaped at all); Make's wildcards * ? [ ]; '=', ';' and '|',
// which change what a Make rule line means; " ' & < > ^ `, at which Ninja's depfile reader ends a path;
// a trailing backslash (it would escape the separator); a word ending in ')' with a '(' (Make's
// archive(member) syntax).
std::optional<std::string> depfile_escape(const std::string& path, std::string* refused = nullptr) {
  auto refuse = [&](std::string what) -> std::optional<std::string> {
    if (refused) *refused = std::move(what);
    return std::nullopt;
  };
  if (!path.empty() && path.back() == '\\') return refuse("a trailing backslash");
  if (path.find('(') != std::string::npos && !path.empty() && path.back() == ')')
    return refuse("'(' and a final ')' (Make reads archive(member))");
  std::string out;
  for (size_t i = 0; i < path.size(); ++i) {
    const char c = path[i];
    if (static_cast<unsigned char>(c) < 0x20 || c == 0x7F) return refuse("a control character");
    if (std::string_view("*?[]=;|\"'&<>^`").find(c) != std::string_view::npos)
      return refuse(std::string("'") + c + "'");
    if (c == ' ' || c == '#' || c == ':') {
      for (size_t k = i; k > 0 && path[k - 1] == '\\'; --k) out += '\\';
      out += '\\';
    }
    if (c == '$') out += '$';
    out += c;
  }
  return out;
}

// Runs one job of the compile stages on a thread with the compiler's stack (nesting_bound.hpp):
// glslang, SPIRV-Tools and SPIRV-Cross recurse as deep as a shader nests. In the compile stages'
// loops (parallel_on_stacks) that is the loop's own thread. The error when no such thread can be made,
// else "".
std::string on_compile_stack(const std::function<void()>& job) {
  std::string error;
  run_on_stack(kCompileStackBytes, job, error);
  return error;
}

// A file name from an object name: keeps letters, digits, space, '-', '_' and '.'.
std::string file_name_of(const std::string& name) {
  std::string out;
  for (char c : name)
    out += (std::isalnum(static_cast<unsigned char>(c)) || c == ' ' || c == '-' || c == '_') ? c : '_';
  return out.empty() ? "_" : out;
}

constexpr const char* kNotInCache =
    "not in the compile cache (local or remote), and --no-compile forbids compiling it";

// Whether a compile key falls in shard `shard` of `shards` (1-based): its first 8 bytes modulo the count.
bool in_shard(const CacheKey& key, uint32_t shard, uint32_t shards) {
  uint64_t point = 0;
  for (size_t i = 0; i < 8; ++i) point = point << 8 | key[i];
  return point % shards == shard - 1;
}

// A compile and its reflection from the cache, when it has both. Runs on any thread: nothing in it
// recurses as a shader nests, so a hit needs no compile stack (a thread made per shader was most of a
// warm pack of small shaders).
bool compile_from_cache(const ShaderDesc& shader, const CompileOptions& options, CompileCache* cache,
                        CompiledShader& compiled, Reflection& reflection,
                        const CompileCache::KnownText* known = nullptr) {
  if (!cache) return false;
  auto hit = cache->find_compile(shader, options, known);
  if (!hit || !hit->reflection) return false;  // (every entry statepack writes has its reflection)
  compiled = std::move(hit->compiled);
  reflection = std::move(*hit->reflection);
  return true;
}

// A compile and its reflection, kept in the cache. On the compile stack.
void compile_and_keep(const ShaderDesc& shader, const CompileOptions& options, ShaderMessages& errors,
                      CompileCache* cache, CompiledShader& compiled, Reflection& reflection) {
  compiled = compile_shader(shader, options, errors);
  if (!compiled.ok) return;
  reflection = reflect_spirv(compiled.spirv, shader.stage);
  if (cache) cache->keep_compile(shader, options, compiled, &reflection);
}

// finalize_spirv's result from the cache, when it has it (any thread, as compile_from_cache).
bool finalized_from_cache(std::vector<uint32_t>& words, const CompileOptions& options, CompileCache* cache) {
  if (!cache) return false;
  auto hit = cache->find_finalized(words, options);
  if (!hit) return false;
  words = std::move(*hit);
  return true;
}

// finalize_spirv, kept in the cache. On the compile stack.
std::string finalize_and_keep(std::vector<uint32_t>& words, const CompileOptions& options,
                              CompileCache* cache) {
  std::vector<uint32_t> input = cache ? words : std::vector<uint32_t>();
  std::string error = finalize_spirv(words, options);
  if (cache && error.empty()) cache->keep_finalized(input, options, words);
  return error;
}

// Both: from the cache when it has the result. On the compile stack.
std::string finalize_cached(std::vector<uint32_t>& words, const CompileOptions& options,
                            CompileCache* cache) {
  return finalized_from_cache(words, options, cache) ? "" : finalize_and_keep(words, options, cache);
}

// Optimises, strips and validates each distinct module once, on all cores: the same patched module
// used by several pipelines is finalised once.
class Finalizer {
 public:
  Finalizer(const CompileOptions& options, CompileCache* cache, const RepackMemo* memo)
      : options_(options), cache_(cache), memo_(memo) {}
  // `optimize` false: the shader said ShaderOptimizationLevel DISABLED; it is validated (and stripped)
  // but never optimised.
  // The same module requested twice (a shader in several pipelines, patched alike) is one job: found by
  // XXH3, then compared word by word (a collision must not merge modules). Until 0.5.6 a copy of every
  // module was kept as the key (100 MB or more for 1,000 real-sized shaders).
  size_t request(std::vector<uint32_t> words, bool optimize) {
    const uint64_t hash = module_hash(words, optimize);
    for (auto [it, end] = job_by_hash_.equal_range(hash); it != end; ++it)
      if (jobs_[it->second].optimize == optimize && jobs_[it->second].words == words) return it->second;
    job_by_hash_.emplace(hash, jobs_.size());
    jobs_.push_back({std::move(words), {}, optimize, {}});
    return jobs_.size() - 1;
  }
  void run(uint32_t threads) {
    CompileOptions unoptimized = options_;
    unoptimized.optimization = Optimization::none;
    parallel_on_stacks(jobs_.size(), threads, kCompileStackBytes, [&](size_t i) {
      const CompileOptions& options = jobs_[i].optimize ? options_ : unoptimized;
      if (memo_) {
        if ((jobs_[i].held = memo_->finalized(jobs_[i].words, jobs_[i].optimize))) {
          if (cache_) cache_->note_used(jobs_[i].held->entry);
          return;
        }
        jobs_[i].input = jobs_[i].words;  // (for the memo's next pack)
      }
      if (finalized_from_cache(jobs_[i].words, options, cache_)) return;
      if (std::string failed =
              on_compile_stack([&] { jobs_[i].error = finalize_and_keep(jobs_[i].words, options, cache_); });
          !failed.empty())
        jobs_[i].error = failed;
    });
  }
  const std::vector<uint32_t>& words(size_t job) const {
    return jobs_[job].held ? jobs_[job].held->output : jobs_[job].words;
  }
  const std::string& error(size_t job) const { return jobs_[job].error; }
  // Each module finalised without an error, before and after: for the memo's next pack.
  std::vector<RepackMemo::Made::MadeModule> made() const {
    std::vector<RepackMemo::Made::MadeModule> out;
    for (const Job& j : jobs_)
      if (j.held || (j.error.empty() && !j.input.empty()))
        out.push_back({j.held, &j.input, j.optimize, &j.words});
    return out;
  }

 private:
  struct Job {
    std::vector<uint32_t> words;
    std::string error;
    bool optimize = true;
    std::vector<uint32_t> input;                        // with a memo: the module before
    std::shared_ptr<const RepackMemo::Finalized> held;  // what the memo had: `words` is left as it came
  };
  const CompileOptions& options_;
  CompileCache* cache_;
  const RepackMemo* memo_;
  std::multimap<uint64_t, size_t> job_by_hash_;  // (requests come before run(), which rewrites `words`)
  std::vector<Job> jobs_;
};

// Writes --dump_dir files, each atomically and never over an input of the run.
class Dumper {
 public:
  Dumper(std::optional<fs::path> dir, const CompileOptions& options, const std::vector<InputFile>& inputs)
      : dir_(std::move(dir)), options_(options), inputs_(inputs) {}
  void write(const fs::path& relative, const std::vector<uint32_t>& words, std::string& error) {
    if (!dir_ || !error.empty()) return;
    fs::path base = *dir_ / "Vulkan" / relative;
    std::error_code ec;
    fs::create_directories(base.parent_path(), ec);
    if (ec) {
      error = "cannot create the dump directory '" + base.parent_path().string() + "': " + ec.message();
      return;
    }
    std::string text = disassemble_spirv(words, options_);
    detail::OutputSet files(inputs_);
    Result<void> written = files.stage(fs::path(base) += ".spv",
                                       {reinterpret_cast<const uint8_t*>(words.data()), words.size() * 4});
    if (written)
      written = files.stage(fs::path(base) += ".spvasm",
                            {reinterpret_cast<const uint8_t*>(text.data()), text.size()});
    if (written) written = files.commit();
    if (!written) error = written.error().message;
  }

 private:
  std::optional<fs::path> dir_;
  const CompileOptions& options_;
  const std::vector<InputFile>& inputs_;
};

// --- the four stages of a pack: compile, plan, assemble, write ------------------------------------

// Every distinct shader of the notation, compiled once and reflected, and which of them each pipeline
// and each Shaders entry uses.
struct CompiledShaders {
  std::vector<CompiledUnit> units;
  std::vector<std::string> unit_keys;               // per unit: its unit_key
  std::vector<std::vector<size_t>> pipeline_units;  // per pipeline: the units of its stages
  // Per pipeline: its own description of each of those stages. Pipelines that share a compiled unit
  // still have their own shader names and notation places, which their messages and records use.
  // Empty for the OpenGL units, whose descriptions differ from the notation's (a translated shader's
  // entry point is "main"): there each stage is the unit's own description.
  std::vector<std::vector<const ShaderDesc*>> pipeline_descs;
  std::vector<size_t> standalone_units;  // per Shaders entry

  // The stages of pipeline `i` for layout and checks; nullopt when one did not compile.
  std::optional<std::vector<StageInput>> stages_of(size_t i) const {
    std::vector<StageInput> stages;
    for (size_t k = 0; k < pipeline_units[i].size(); ++k) {
      const CompiledUnit& unit = units[pipeline_units[i][k]];
      if (!unit.compiled.ok) return std::nullopt;
      stages.push_back({pipeline_descs.empty() ? &unit.desc : pipeline_descs[i][k], &unit.compiled.spirv,
                        &unit.reflection, unit.module ? &*unit.module : nullptr,
                        unit.compiled.vertex_semantics.empty() ? nullptr : &unit.compiled.vertex_semantics,
                        unit.compiled.entry_point});
    }
    return stages;
  }
};

// Compiles on all cores. Every shader whose own description is usable is compiled, even when other
// objects have notation errors, so one run reports both (docs/cli.md).
// `pipelines_only`: the standalone Shaders are left out (--opengl alone: its block stores pipelines only).
CompiledShaders compile_shaders(const Notation& notation, const PackOptions& options, Diagnostics& diag,
                                bool pipelines_only, CompileCache* cache, const ArchiveKey* record,
                                const RepackMemo* memo) {
  CompiledShaders out;
  // The shader files the record's key read and hashed are not read again, so a hit and the record agree
  // on one text per file (a miss compiles what the file holds then, and the record check after the pack
  // catches a file saved since the key).
  const std::map<fs::path, CompileCache::KnownText> no_texts;
  const auto& known = record ? record->shader_texts : no_texts;
  std::map<std::string, size_t> unit_by_key;
  auto unit_for = [&](const ShaderDesc& s) {
    auto [it, inserted] = unit_by_key.try_emplace(unit_key(s), out.units.size());
    if (inserted) {
      out.units.push_back({s, {}, {}});
      out.unit_keys.push_back(it->first);
    }
    return it->second;
  };
  for (const auto& p : notation.pipelines) {
    out.pipeline_units.emplace_back();
    out.pipeline_descs.emplace_back();
    for (const auto& s : p.shaders)
      if (!s.is_reference) {
        out.pipeline_units.back().push_back(unit_for(s));
        out.pipeline_descs.back().push_back(&s);
      }
  }
  if (!pipelines_only)
    for (const auto& s : notation.shaders) out.standalone_units.push_back(unit_for(s));
  ShaderMessages compile_errors;  // an error in a shared #include is reported once
  parallel_on_stacks(out.units.size(), options.threads, kCompileStackBytes, [&](size_t i) {
    CompiledUnit& u = out.units[i];
    if (u.desc.broken) return;  // its notation errors are reported; compiling it would guess
    if (options.shards) {       // --shard: another machine compiles what falls in another shard
      const auto key = compile_cache_key(u.desc, options.compile);
      if (key && !in_shard(*key, options.shard, options.shards)) return;
      u.in_shard = true;
    }
    // (only a compile that passed everything below is held; not with --no-compile, which must find
    // each compile in the cache as it is now)
    if (auto held = memo && !options.compile.no_compile ? memo->unit(out.unit_keys[i]) : nullptr) {
      u.compiled = held->compiled;
      u.reflection = held->reflection;
      u.module = held->module;
      // (an inline Source's entry is named by the shader's name too, which its unit_key leaves out)
      if (cache)
        cache->note_used(u.desc.file.empty()
                             ? compile_entry_key(u.desc, options.compile, u.compiled.source_hash)
                             : held->entry);
      u.held = std::move(held);
      return;
    }
    const auto text = u.desc.file.empty()
                          ? known.end()
                          : known.find((working_directory() / u.desc.file).lexically_normal());
    if (!compile_from_cache(u.desc, options.compile, cache, u.compiled, u.reflection,
                            text == known.end() ? nullptr : &text->second)) {
      if (options.compile.no_compile)
        return diag.error(u.desc.where, "shader '" + u.desc.name + "': " + kNotInCache);
      u.compiled_here = true;
      if (std::string failed = on_compile_stack([&] {
            compile_and_keep(u.desc, options.compile, compile_errors, cache, u.compiled, u.reflection);
          });
          !failed.empty())
        return diag.error(u.desc.where, "shader '" + u.desc.name + "': " + failed);
    }
    if (!u.compiled.ok) return;
    if (auto walked = spirv::walk(u.compiled.spirv)) u.module = std::move(*walked);  // here: on all cores
    for (ReflectedBinding& b : u.reflection.bindings)
      b.combined_attribute =
          std::find(u.compiled.combined_image_samplers.begin(), u.compiled.combined_image_samplers.end(),
                    b.name) != u.compiled.combined_image_samplers.end();
    if (!u.reflection.error.empty()) {
      u.compiled.ok = false;
      diag.error(u.desc.where,
                 "shader '" + u.desc.name + "': SPIR-V reflection failed: " + u.reflection.error);
    } else if (!u.reflection.unsupported.empty()) {
      u.compiled.ok = false;
      diag.error(u.desc.where, "shader '" + u.desc.name + "' " + u.reflection.unsupported);
    }
  });
  compile_errors.report(diag);
  return out;
}

// The stages as the pipeline's checks see them: an HLSL vertex shader whose inputs InputLayout places by
// semantic is checked with its inputs where they are moved to (in `patched`, the pipeline's copy of the
// module, and in `vs_reflection`). nullopt, with an error, when they cannot be placed.
std::optional<std::vector<StageInput>> place_vertex_inputs(const PipelineDesc& p,
                                                           const std::vector<StageInput>& stages,
                                                           std::vector<std::vector<uint32_t>>& patched,
                                                           Reflection& vs_reflection,
                                                           const SourceTexts& sources, Diagnostics& diag) {
  std::vector<StageInput> out = stages;
  for (size_t s = 0; s < stages.size(); ++s) {
    if (stages[s].desc->stage != VK_SHADER_STAGE_VERTEX_BIT || !stages[s].semantics) continue;
    vs_reflection = *stages[s].reflection;
    if (!place_inputs_by_semantic(p, stages[s], patched[s], vs_reflection, sources, diag))
      return std::nullopt;
    out[s].reflection = &vs_reflection;
  }
  return out;
}

// A pipeline laid out and checked, its patched modules queued for finalising.
struct PendingPipeline {
  format::Pipeline pipeline;
  std::vector<const ShaderDesc*> stages;
  std::vector<std::string> entry_points;  // per stage, its module's
  std::vector<size_t> jobs;               // Finalizer jobs, per stage
  const PipelineDesc* desc;
};

struct Plan {
  std::vector<PendingPipeline> pipelines;
  std::vector<size_t> standalone_jobs;  // per Shaders entry: its Finalizer job, or kNoJob
};

// Signatures and render passes into the archive, then each pipeline's layout, constants and checks
// against its shaders (serial and cheap); the modules to optimise and validate go to `finalizer`. A
// shader that failed to compile stops only the pipelines that use it, so the others are still laid out
// and checked and their errors reported.
Plan plan_archive(const Notation& notation, const CompiledShaders& compiled,
                  const LayoutOptions& layout_options, ContentsBuilder& builder, Finalizer& finalizer,
                  Diagnostics& diag) {
  Plan plan;
  plan.pipelines.reserve(notation.pipelines.size());  // (a pipeline moved is copied: reserve, not grow)
  builder.contents.pipelines.reserve(notation.pipelines.size());
  // Every signature and render pass is archived by name, used or not; Ignore.Signatures are not.
  for (const auto& sig : notation.signatures)
    if (!notation.ignored_signatures.count(sig.name))
      builder.add_set_layout(signature_set_layout(sig, true, builder));
  std::map<std::string, uint32_t> pass_index;
  for (const auto& rp : notation.render_passes) {
    pass_index[rp.pass.name] = builder.add_render_pass(rp.pass);
    warn_render_pass_formats(rp, notation.sources, diag);
  }

  WalkedModules walked;  // compute shaders, for their work-group size
  const auto& units = compiled.units;
  for (size_t u : compiled.standalone_units)
    plan.standalone_jobs.push_back(
        units[u].compiled.ok ? finalizer.request(units[u].compiled.spirv, units[u].desc.optimize) : kNoJob);
  for (size_t i = 0; i < notation.pipelines.size(); ++i) {
    const PipelineDesc& p = notation.pipelines[i];
    const auto compiled_stages = compiled.stages_of(i);
    if (!compiled_stages) continue;  // its compile errors are reported; the other pipelines go on
    PipelineLayout layout;
    if (!build_pipeline_layout(p, *compiled_stages, notation, builder, layout_options, layout, diag))
      continue;
    Reflection vs_reflection;
    const auto placed =
        place_vertex_inputs(p, *compiled_stages, layout.patched_spirv, vs_reflection, notation.sources, diag);
    if (!placed) continue;
    const std::vector<StageInput>& stages = *placed;
    std::vector<format::SpecConstant> constants;
    if (!resolve_constants(p, stages, constants, diag)) continue;
    PendingPipeline pp{{}, {}, {}, {}, &p};
    format::Pipeline& out_pipeline = pp.pipeline;
    out_pipeline.name = p.name;
    out_pipeline.kind = p.kind;
    out_pipeline.graphics = p.graphics;
    out_pipeline.set_layouts = layout.set_layouts;
    out_pipeline.push_constant_size = layout.push_constant_size;
    out_pipeline.push_constant_stages = layout.push_constant_stages;
    out_pipeline.dynamic_states = p.kind == format::PipelineKind::graphics ? p.dynamic_states : 0;
    out_pipeline.constants = std::move(constants);
    if (!p.render_pass.empty()) {
      out_pipeline.render_pass = pass_index.at(p.render_pass);
      out_pipeline.subpass = p.subpass;  // its formats are in p.graphics (resolve_references applied them)
    }
    if (p.kind == format::PipelineKind::graphics &&
        !check_graphics_interfaces(p, out_pipeline.graphics, stages, notation.sources, diag))
      continue;
    if (p.kind == format::PipelineKind::compute && !stages.empty())
      warn_compute_work_group(p, stages.front(), out_pipeline.constants, walked, diag);
    for (size_t s = 0; s < stages.size(); ++s) {
      pp.stages.push_back(stages[s].desc);
      pp.entry_points.emplace_back(stages[s].entry_point);
      pp.jobs.push_back(finalizer.request(std::move(layout.patched_spirv[s]), stages[s].desc->optimize));
    }
    plan.pipelines.push_back(std::move(pp));
  }
  return plan;
}

// What a backend-specific GLSL source (one that tests VULKAN or GL_SPIRV, compiled for OpenGL from its
// own text) declares that OpenGL has no binding for: separate samplers and sampled images, input
// attachments. glslang's OpenGL front end would only report a syntax error at the declaration
// ("unexpected IDENTIFIER"), so they are refused by name instead. `""` when there are none.
std::string refused_for_opengl(const CompiledUnit& vulkan) {
  std::string names;
  for (const ReflectedBinding& b : vulkan.reflection.bindings)
    if (!format::gl_namespace_of(b.descriptor_type))
      names += std::string(names.empty() ? "" : ", ") + "'" + b.name + "' (" +
               format::descriptor_type_name(b.descriptor_type) + ")";
  if (names.empty()) return "";
  return "shader '" + vulkan.desc.name + "' (OpenGL): declares " + names +
         " when VULKAN is not defined, which OpenGL does not have; use combined samplers (sampler2D and "
         "the like) there, or drop the #ifdef VULKAN branches to let statepack translate the Vulkan code";
}

// One shader for OpenGL from its Vulkan unit: SPIR-V translated (gl_translate.hpp), or, for GLSL that
// tests VULKAN or GL_SPIRV, its own text compiled again with glslang's OpenGL client.
void make_opengl_unit(const CompiledUnit& vulkan, const PackOptions& options, CompiledUnit& out,
                      ShaderMessages& direct_errors, Diagnostics& diag, CompileCache* cache) {
  const std::string who = "shader '" + vulkan.desc.name + "' (OpenGL)";
  out.desc = vulkan.desc;
  // --shard fills the caches: a translation is not kept in one (the assembling pack makes it).
  if (options.shards && !vulkan.compiled.backend_specific) return;
  // translated modules' (GL namespace, binding number) -> names
  std::map<std::pair<uint32_t, uint32_t>, std::string> name_of_binding;
  if (std::string exceeded = gl_units_exceeded(vulkan.reflection.bindings); !exceeded.empty()) {
    diag.error(vulkan.desc.where, who + ": " + exceeded);
    return;
  }
  if (vulkan.compiled.backend_specific) {
    if (std::string refused = refused_for_opengl(vulkan); !refused.empty()) {
      diag.error(vulkan.desc.where, refused);
      return;
    }
    CompileOptions gl = options.compile;
    gl.opengl = true;
    if (!compile_from_cache(vulkan.desc, gl, cache, out.compiled, out.reflection)) {
      if (gl.no_compile) return diag.error(vulkan.desc.where, who + ": " + kNotInCache);
      compile_and_keep(vulkan.desc, gl, direct_errors, cache, out.compiled, out.reflection);
    }
  } else {
    // What is translated must be valid SPIR-V: SPIRV-Cross would carry a fault (two outputs at one
    // location, as glslang makes of some HLSL) into GLSL that then fails to compile. With --vulkan the
    // Vulkan stage reports the same fault at the pipeline.
    CompileOptions check = options.compile;
    check.optimization = Optimization::none;
    check.strip_debug_info = false;
    std::vector<uint32_t> copy = vulkan.compiled.spirv;
    if (std::string invalid = finalize_spirv(copy, check); !invalid.empty()) {
      if (!options.vulkan) diag.error(vulkan.desc.where, who + ": " + invalid);
      return;
    }
    GlTranslation t = translate_for_opengl(vulkan.compiled.spirv, "_sampler");
    if (!t.unsupported.empty()) {
      diag.error(vulkan.desc.where, who + ": uses " + t.unsupported + ", which OpenGL 4.5 does not have");
      return;
    }
    if (!t.error.empty()) {
      diag.error(vulkan.desc.where,
                 who + ": SPIRV-Cross cannot translate its Vulkan SPIR-V to GLSL: " + t.error);
      return;
    }
    std::string log;
    out.compiled.spirv = compile_generated_glsl(t.glsl, vulkan.desc.stage, log);
    if (out.compiled.spirv.empty()) {
      while (!log.empty() && (log.back() == '\n' || log.back() == ' ')) log.pop_back();
      for (char& c : log)
        if (c == '\n') c = ' ';
      diag.error(vulkan.desc.where, who +
                                        ": the GLSL translated from its Vulkan SPIR-V does not compile for "
                                        "OpenGL 4.5 (a statepack limitation worth reporting): " +
                                        log);
      return;
    }
    out.desc.entry_point = out.compiled.entry_point = "main";  // SPIRV-Cross names the entry point main
    out.compiled.ok = true;
    out.reflection = reflect_spirv(out.compiled.spirv, out.desc.stage);  // (compile_cached reflects its own)
    // The translation keeps each input's location: its semantic follows it there.
    for (const VertexInputSemantic& s : vulkan.compiled.vertex_semantics)
      for (const InterfaceVariable& v : vulkan.reflection.inputs)
        if (v.variable == s.variable)
          for (const InterfaceVariable& g : out.reflection.inputs)
            if (g.location == v.location) out.compiled.vertex_semantics.push_back({g.variable, s.semantic});
    name_of_binding = std::move(t.name_of_binding);
  }
  if (!out.compiled.ok) return;
  if (!out.reflection.error.empty()) {
    out.compiled.ok = false;
    diag.error(vulkan.desc.where, who + ": SPIR-V reflection failed: " + out.reflection.error);
  }
  for (ReflectedBinding& b : out.reflection.bindings)  // translated: the Vulkan names, whatever GLSL allowed
    if (auto kind = format::gl_namespace_of(b.descriptor_type))
      if (auto it = name_of_binding.find({uint32_t(*kind), b.binding}); it != name_of_binding.end())
        b.name = it->second;
}

// Every pipeline's shaders for OpenGL, unit for unit beside the Vulkan ones (the same pipeline_units),
// on all cores. Standalone Shaders are left out: the OpenGL block stores pipelines only.
CompiledShaders opengl_units(const CompiledShaders& vulkan, const PackOptions& options, Diagnostics& diag,
                             CompileCache* cache) {
  CompiledShaders out;
  out.pipeline_units = vulkan.pipeline_units;
  out.units.resize(vulkan.units.size());
  std::vector<char> used(vulkan.units.size(), 0);
  for (const auto& units : vulkan.pipeline_units)
    for (size_t u : units) used[u] = 1;
  ShaderMessages direct_errors;
  parallel_on_stacks(vulkan.units.size(), options.threads, kCompileStackBytes, [&](size_t u) {
    if (!used[u] || !vulkan.units[u].compiled.ok) return;
    if (std::string failed = on_compile_stack(
            [&] { make_opengl_unit(vulkan.units[u], options, out.units[u], direct_errors, diag, cache); });
        !failed.empty())
      diag.error(vulkan.units[u].desc.where,
                 "shader '" + vulkan.units[u].desc.name + "' (OpenGL): " + failed);
  });
  direct_errors.report(diag);
  return out;
}

// The OpenGL backend: each pipeline from its shaders compiled for OpenGL, with its own binding table
// (gl_layout.hpp). Specialization constants are resolved as for Vulkan; when Vulkan is packed too its
// stage has reported any error in them already.
void add_opengl(const Notation& notation, const CompiledShaders& compiled, const PackOptions& options,
                ContentsBuilder& builder, Diagnostics& diag, CompileCache* cache) {
  CompileOptions gl_options = options.compile;
  gl_options.opengl = true;
  CompileOptions gl_unoptimized = gl_options;
  gl_unoptimized.optimization = Optimization::none;
  Diagnostics reported_by_vulkan(0);
  for (size_t i = 0; i < notation.pipelines.size(); ++i) {
    const PipelineDesc& p = notation.pipelines[i];
    const auto compiled_stages = compiled.stages_of(i);
    if (!compiled_stages) continue;  // its compile errors are reported
    GlLayout layout;
    if (!build_gl_layout(p, *compiled_stages, layout, diag)) continue;
    Reflection vs_reflection;  // with Vulkan packed too, its stage has reported what this finds
    const auto placed = place_vertex_inputs(p, *compiled_stages, layout.patched_spirv, vs_reflection,
                                            notation.sources, options.vulkan ? reported_by_vulkan : diag);
    if (!placed) continue;
    const std::vector<StageInput>& stages = *placed;
    std::vector<format::SpecConstant> constants;
    if (!resolve_constants(p, stages, constants, options.vulkan ? reported_by_vulkan : diag)) continue;
    if (auto wide =
            std::find_if(constants.begin(), constants.end(), [](const auto& k) { return k.size != 4; });
        wide != constants.end()) {
      diag.error(p.where, "pipeline '" + p.name + "' (OpenGL): specialization constant '" + wide->name +
                              "' is 64-bit; glSpecializeShader takes 32-bit values only");
      continue;
    }
    // With Vulkan packed too, its stage has checked the notation against the shaders already.
    if (!options.vulkan && p.kind == format::PipelineKind::graphics &&
        !check_graphics_interfaces(p, p.graphics, stages, notation.sources, diag))
      continue;
    format::GlPipeline out{p.name, p.kind, {}, std::move(layout.bindings), {}, std::move(constants)};
    if (p.kind == format::PipelineKind::graphics) {
      out.graphics = p.graphics;  // with its subpass's formats
      // OpenGL takes formats from the framebuffer; what it needs is a blend state for every target the
      // pixel shader writes, also those the notation leaves to run time (their blend state is stored).
      for (const StageInput& stage : stages)
        if (stage.desc->stage == VK_SHADER_STAGE_FRAGMENT_BIT)
          if (auto module = spirv::walk(*stage.spirv))
            out.graphics.color_count =
                std::max<uint32_t>(out.graphics.color_count,
                                   std::min<uint32_t>(format::kMaxColorTargets,
                                                      32 - std::countl_zero(module->output_location_mask())));
    }
    bool ok = true;
    for (size_t s = 0; s < stages.size(); ++s) {
      std::vector<uint32_t>& spirv = layout.patched_spirv[s];
      if (std::string error =
              finalize_cached(spirv, stages[s].desc->optimize ? gl_options : gl_unoptimized, cache);
          !error.empty()) {
        diag.error(stages[s].desc->where,
                   "shader '" + stages[s].desc->name + "' (OpenGL): SPIR-V validation failed: " + error);
        ok = false;
        continue;
      }
      out.shaders.push_back({stages[s].desc->name, stages[s].desc->stage, builder.add_blob(spirv),
                             std::string(stages[s].entry_point)});
    }
    if (ok) builder.contents.gl_pipelines.push_back(std::move(out));
  }
}

// The finalised modules into the archive in notation order, so the archive does not depend on thread
// timing; --dump_dir files written beside.
void assemble_archive(const Notation& notation, const CompiledShaders& compiled, Plan& plan,
                      const Finalizer& finalizer, ContentsBuilder& builder, Dumper& dumper,
                      std::string& io_error, Diagnostics& diag) {
  for (size_t s = 0; s < notation.shaders.size(); ++s) {
    const CompiledUnit& unit = compiled.units[compiled.standalone_units[s]];
    size_t job = plan.standalone_jobs[s];
    if (job == kNoJob) continue;  // did not compile
    if (!finalizer.error(job).empty()) {
      diag.error(unit.desc.where, "shader '" + unit.desc.name + "': " + finalizer.error(job));
      continue;
    }
    dumper.write(fs::path("shaders") / file_name_of(unit.desc.name), finalizer.words(job), io_error);
    uint32_t blob = builder.add_blob(finalizer.words(job));
    builder.contents.standalone_shaders.push_back(
        builder.add_shader({unit.desc.name, unit.desc.stage, blob, unit.compiled.entry_point}));
  }
  for (PendingPipeline& pp : plan.pipelines) {
    const PipelineDesc& p = *pp.desc;
    bool ok = true;
    for (size_t s = 0; s < pp.stages.size(); ++s) {
      size_t job = pp.jobs[s];
      if (!finalizer.error(job).empty()) {
        // At the pipeline's own shader slot: the module is the one this pipeline's layout patched.
        diag.error(pp.stages[s]->where,
                   "pipeline '" + p.name + "', shader '" + pp.stages[s]->name + "': " + finalizer.error(job));
        ok = false;
        continue;
      }
      const std::string kind =
          p.kind == format::PipelineKind::compute ? "compute" : "graphics";  // as Diligent
      dumper.write(fs::path(kind) / file_name_of(p.name) / file_name_of(pp.stages[s]->name),
                   finalizer.words(job), io_error);
      uint32_t blob = builder.add_blob(finalizer.words(job));
      pp.pipeline.shaders.push_back(
          builder.add_shader({pp.stages[s]->name, pp.stages[s]->stage, blob, pp.entry_points[s]}));
    }
    if (ok) builder.contents.pipelines.push_back(std::move(pp.pipeline));
  }
}

// Objects no pipeline uses are still archived (unpackable by name); say so, as they may be typos.
void note_unused_objects(const Notation& notation, Diagnostics& diag) {
  std::set<std::string> used_passes, used_signatures;
  for (const auto& p : notation.pipelines) {
    used_passes.insert(p.render_pass);
    used_signatures.insert(p.signatures.begin(), p.signatures.end());
  }
  for (const auto& rp : notation.render_passes)
    if (!used_passes.count(rp.pass.name))
      diag.note(rp.where, "render pass '" + rp.pass.name + "' is used by no pipeline (archived anyway)");
  for (const auto& sig : notation.signatures)
    if (!used_signatures.count(sig.name))
      diag.note(sig.where, "resource signature '" + sig.name + "' is used by no pipeline (archived anyway)");
}

// Archive and depfile, all or nothing: both to temporaries, then both renamed. Returns the exit code.
int write_outputs(const PackOptions& options, const std::vector<InputFile>& inputs,
                  std::span<const uint8_t> bytes, std::ostream& err) {
  detail::OutputSet outputs(inputs);
  std::string text;
  if (options.depfile) {
    // Make syntax: "<output>: <every JSON and shader file read>".
    std::set<std::string> deps;
    for (const auto& f : inputs) deps.insert(f.path.string());
    text = ":";
    for (const auto& path : deps) text += " \\\n  " + depfile_escape(path).value_or("");
    text += "\n";
    deps.insert(options.output.string());
    for (const auto& path : deps)
      if (std::string refused; !depfile_escape(path, &refused)) {
        err << "statepack: error: cannot write the depfile: the path '" << printable(path) << "' holds "
            << printable(refused)
            << ", which Make and Ninja cannot both read in a depfile; rename it, or pack without --depfile\n";
        return kExitIoError;
      }
    text = *depfile_escape(options.output.string()) + text;
  }
  Result<void> written = outputs.stage(options.output, bytes);
  if (written && options.depfile)
    written = outputs.stage(*options.depfile, {reinterpret_cast<const uint8_t*>(text.data()), text.size()});
  if (written) written = outputs.commit();
  if (!written) {
    err << "statepack: error: " << printable(written.error().message) << '\n';
    return exit_code_of_output_error(written.error());
  }
  return kExitSuccess;
}

// Why an output of this pack can never be written (checked before any work; inputs are checked once
// known), or empty. A device or directory given as the output gets a hint for packing without one.
std::string output_refusal(const PackOptions& options) {
  if (options.check_only || options.shards) return "";
  detail::OutputSet none({});
  for (const auto* path : {&options.output, options.depfile ? &*options.depfile : nullptr}) {
    if (!path) continue;
    if (std::string reason = none.refuse_reason(*path); !reason.empty()) {
      std::error_code ec;
      const auto kind = fs::symlink_status(*path, ec).type();
      if (kind != fs::file_type::regular && kind != fs::file_type::symlink &&
          kind != fs::file_type::not_found)
        reason += " (use --check to pack without writing)";
      return reason;
    }
  }
  return "";
}

// Prints the warnings of a cache's flush and notes this pack's share of its statistics (a cache may serve
// several packs) for --time-report.
void report_flush(const CompileCache& cache, const CompileCache::Stats& before,
                  const std::string& flush_warning, const RemoteCache* remote, PhaseTimes& times,
                  std::ostream& err) {
  if (!flush_warning.empty()) err << "statepack: warning: --cache-dir: " << flush_warning << "\n";
  const CompileCache::Stats s = cache.stats();
  std::string note =
      "cache: " + std::to_string(s.hits - before.hits) + " hits, " +
      std::to_string(s.misses - before.misses) + " misses, " + std::to_string(s.damaged - before.damaged) +
      " damaged, " + std::to_string(s.written - before.written) + " written, " +
      std::to_string(s.removed - before.removed) + " removed; " +
      std::to_string(s.from_bundle - before.from_bundle) + " entries read from the pack's bundle";
  if (remote) {
    const RemoteCache::Stats r = remote->stats();
    note +=
        "; remote: " + std::to_string(s.remote_hits - before.remote_hits) + " hits, " +
        std::to_string(r.misses) + " misses, " + std::to_string(s.remote_refused - before.remote_refused) +
        " refused, " + std::to_string(r.errors) + " errors, " + std::to_string(r.written) + " written, " +
        std::to_string(r.bytes_read) + " bytes read, " + std::to_string(r.bytes_written) + " bytes written";
    if (std::string warning = remote->warning(); !warning.empty())
      for (size_t at = 0; at < warning.size();) {
        const size_t end = std::min(warning.find('\n', at), warning.size());
        err << "statepack: warning: " << warning.substr(at, end - at) << "; the pack went on without it\n";
        at = end + 1;
      }
    if (size_t refused = s.remote_refused - before.remote_refused)
      err << "statepack: warning: remote cache: " << refused << " entr" << (refused == 1 ? "y" : "ies")
          << " refused (the first, " << printable(cache.first_refusal()) << "); made here instead\n";
  }
  times.note(note);
  times.done("cache");
}

// Writes what the pack kept to the cache (a warning when it cannot), and reports it.
void flush_cache(CompileCache& cache, const CompileCache::Stats& before, const std::vector<InputFile>& inputs,
                 const RemoteCache* remote, PhaseTimes& times, std::ostream& err) {
  report_flush(cache, before, cache.flush(inputs), remote, times, err);
}

// Work on a thread of its own (it returns a warning, or ""), reported on the pack's thread when joined: by
// finish(), or by the destructor whichever way the pack ends.
class ReportedThread {
 public:
  ReportedThread() = default;
  ReportedThread(const ReportedThread&) = delete;
  ReportedThread& operator=(const ReportedThread&) = delete;
  ~ReportedThread() { finish(); }
  void start(std::function<std::string()> work, std::function<void(const std::string&)> report) {
    report_ = std::move(report);
    thread_ = std::thread([this, work = std::move(work)] { warning_ = work(); });
  }
  void finish() {
    if (!thread_.joinable()) return;
    thread_.join();
    report_(warning_);
  }

 private:
  std::function<void(const std::string&)> report_;
  std::string warning_;
  std::thread thread_;
};

// The cache written on a thread of its own while the pack encodes, checks and writes the archive (a
// cold pack writes a file per compile and finalisation, a pack from a server keeps every entry it
// fetched, and sends what it compiled).
void flush_in_background(ReportedThread& thread, CompileCache* cache, const CompileCache::Stats& before,
                         const std::vector<InputFile>& inputs, const RemoteCache* remote, PhaseTimes& times,
                         std::ostream& err) {
  if (!cache) return;
  thread.start([cache, &inputs] { return cache->flush(inputs); },
               [cache, before, remote, &times, &err](const std::string& warning) {
                 report_flush(*cache, before, warning, remote, times, err);
               });
}

// --shard K/N: the compiles are in the caches; nothing is laid out or written. Says what the shard did.
int finish_shard(const PackOptions& options, const CompiledShaders& compiled, CompileCache& cache,
                 const CompileCache::Stats& before, const std::vector<InputFile>& inputs,
                 const RemoteCache* remote, PhaseTimes& times, Diagnostics& diag, std::ostream& out,
                 std::ostream& err) {
  flush_cache(cache, before, inputs, remote, times, err);
  size_t mine = 0, made = 0;
  for (const CompiledUnit& u : compiled.units) mine += u.in_shard, made += u.compiled_here;
  diag.print(err);
  if (diag.has_errors()) {
    err << "statepack: " << diag.error_count() << " error(s) in shard " << options.shard << "/"
        << options.shards << "\n";
    return kExitInputError;
  }
  out << "shard " << options.shard << "/" << options.shards << ": " << mine << " of " << compiled.units.size()
      << " shader compiles (" << made << " compiled, " << (mine - made)
      << " already cached); no archive written (--shard)\n";
  return kExitSuccess;
}

// What names a pack for its cache bundle (compile_cache.hpp): where it runs, what it reads first, and
// the options that decide its entries (so that two builds of one notation with other options keep a
// bundle each). Not the output: a pack to another file needs the same entries. Only a guess at which
// entries the pack will need: each is still found by its own key.
std::string bundle_project(const PackOptions& options) {
  std::error_code ec;
  std::string text = working_directory().string();
  for (const auto& input : options.inputs)
    text += "\n-i " + fs::absolute(input, ec).lexically_normal().string();
  const CompileOptions& c = options.compile;
  for (const auto& dir : c.include_dirs) text += "\n-s " + dir.string();
  for (const auto& [name, value] : c.global_macros) text += "\n-D " + name + "=" + value;
  for (uint64_t value : {uint64_t(options.vulkan), uint64_t(options.opengl), uint64_t(c.vulkan_version),
                         uint64_t(c.optimization), uint64_t(c.strip_debug_info),
                         uint64_t(c.shader_environment), c.max_input_bytes})
    text += "\n" + std::to_string(value);
  return text;
}

// The pack's compile cache: the session's, or --cache-dir opened (in memory when only servers are given),
// with the servers behind it and the team's key.
struct PackCache {
  std::optional<CompileCache> owned;
  CompileCache* cache = nullptr;
  std::shared_ptr<RemoteCache> remote;
};
void open_cache(const PackOptions& options, PackSession* session, PackCache& out, std::ostream& err) {
  std::string cache_error;
  const bool own = !(session && session->cache);
  if (options.cache_dir && own)
    if (auto opened = CompileCache::open(*options.cache_dir, options.cache_max_bytes, cache_error))
      out.owned.emplace(std::move(*opened));
  if (!cache_error.empty())
    err << "statepack: warning: --cache-dir: " << cache_error << "; packing without a cache\n";
  if (!options.remote_cache.empty()) out.remote = std::make_shared<RemoteCache>(options.remote_cache);
  if (out.remote && !out.owned && own)
    out.owned.emplace(CompileCache::in_memory(CompileCache::kDefaultMaxBytes));
  out.cache = own ? (out.owned ? &*out.owned : nullptr) : session->cache;
  if (out.cache) {
    out.cache->use_remote(out.remote);
    out.cache->set_signing_key(options.cache_signing_key);
  }
}

// --print-contents: what the archive holds, read back the way the dearchiver reads it.
int print_written(std::span<const uint8_t> bytes, std::ostream& out, std::ostream& err) {
  auto written = format::decode(bytes);
  if (!written) {
    err << "statepack: error: the archive just written does not decode: "
        << printable(written.error().message) << '\n';
    return kExitIoError;
  }
  print_archive(*written, bytes.size(), false, out);
  return kExitSuccess;
}

// A pack whose archive record still holds (archive_reuse.hpp): the recorded bytes written as a pack
// writes them, once they decode (structure and checksum; the modules were checked when it was packed): a
// record is a cache file, and what a pack writes must load. nullopt, having printed nothing, when they do
// not. The compile cache is not flushed: nothing was looked up in it, and its bundle stays the one of the
// shaders' entries, for the pack after the next change.
std::optional<int> write_reused(const PackOptions& options, std::span<const uint8_t> bytes,
                                const std::vector<InputFile>& inputs, PackSession* session, PhaseTimes& times,
                                std::ostream& out, std::ostream& err, bool by_stamps) {
  auto contents = format::decode(bytes);
  if (!contents) return std::nullopt;
  if (session)
    for (const auto& f : inputs) session->files_read.push_back(f.path);
  times.note(by_stamps ? "cache: nothing changed since the pack that recorded this archive (every input "
                         "stats as stamped): its bytes reused, nothing read"
                       : "cache: nothing changed since the pack that recorded this archive: its bytes "
                         "reused, no shader looked up");
  times.done("find the archive record");
  if (!options.check_only)
    if (int code = write_outputs(options, inputs, bytes, err); code != kExitSuccess) return code;
  times.done("write");
  if (options.print_contents) print_archive(*contents, bytes.size(), false, out);
  return kExitSuccess;
}

// The key of this pack's archive record (archive_reuse.hpp), or nullopt: no cache, --no-archive-reuse, a
// cache in memory that dies with this pack (only servers given, no --cache-dir), or what archive_key
// refuses (any message so far, errors included).
std::optional<ArchiveKey> archive_record_key(const PackOptions& options, const PackSession* session,
                                             const CompileCache* cache, const Notation& notation,
                                             const Diagnostics& diag) {
  if (!cache || !options.archive_reuse || !(options.cache_dir || (session && session->cache)))
    return std::nullopt;
  return archive_key(options, bundle_project(options), notation, diag, session ? session->memo : nullptr);
}

// The pack's exit code when its archive record still holds and the recorded archive was written; else
// nullopt: a normal pack.
std::optional<int> reuse_archive(const PackOptions& options, CompileCache& cache, const ArchiveKey& record,
                                 const Notation& notation, PackSession* session, PhaseTimes& times,
                                 std::ostream& out, std::ostream& err,
                                 std::chrono::system_clock::time_point started) {
  std::vector<InputFile> inputs = notation.files_read;
  const auto archive = find_archive(cache, record, options.compile, inputs);
  if (!archive) return std::nullopt;
  const auto code = write_reused(options, archive->bytes, inputs, session, times, out, err, false);
  // The stamps did not hold (or there were none): stamped again, so that the next pack reads nothing.
  if (code == kExitSuccess)
    if (std::string warning = write_input_stamps(
            cache, record.slot,
            {archive->id, record.setup, notation.lookups, inputs, tables_hint(notation, options.compile)},
            started);
        !warning.empty())
      err << "statepack: warning: --cache-dir: " << printable(warning) << "\n";
  return code;
}

// The input stamps of what the pack read (input_stamps.hpp), taken on another core while it lays out,
// encodes and checks its archive: about 1,000 stats for 1,000 shaders, 3 to 5 ms that a repack after an
// edit waited for at its end.
class StampsAhead {
 public:
  StampsAhead() = default;
  StampsAhead(const StampsAhead&) = delete;
  StampsAhead& operator=(const StampsAhead&) = delete;
  ~StampsAhead() {
    if (thread_.joinable()) thread_.join();
  }
  // Once the pack has read its last input. `lookups` and `files` must live until get() or the end.
  void start(const std::vector<FileLookup>& lookups, const std::vector<InputFile>& files,
             std::chrono::system_clock::time_point started) {
    auto take = [this, &lookups, &files, started] {
      try {
        taken_ = take_input_stamps(lookups, files, started);
      } catch (...) {  // (out of memory: no stamps; the next pack reads its inputs)
      }
    };
    try {
      thread_ = std::thread(take);
    } catch (...) {
      take();  // (no thread: taken here)
    }
  }
  const std::optional<TakenStamps>& get() {
    if (thread_.joinable()) thread_.join();
    return taken_;
  }

 private:
  std::thread thread_;
  std::optional<TakenStamps> taken_;
};

// Records this pack's archive for the next pack of the same inputs (archive_reuse.hpp) on a thread of its
// own, while the archive is written. Started after the cache's own flush is done (a record is written
// beside its entries).
// (Everything by reference is the pack's, and outlives `thread`, which the pack joins before it returns.)
void record_in_background(ReportedThread& thread, CompileCache& cache, const ArchiveKey& key,
                          const CompiledShaders& compiled, const CompiledShaders& gl_compiled,
                          const std::vector<InputFile>& inputs, StampsAhead& stamps,
                          std::optional<TablesHint> tables, std::span<const uint8_t> bytes,
                          std::ostream& err) {
  std::vector<const CompiledShader*> compiles;
  for (const auto* c : {&compiled, &gl_compiled})
    for (const auto& u : c->units) compiles.push_back(&u.compiled);
  thread.start([&cache, &key, compiles, &inputs, &stamps, tables = std::move(tables),
                bytes] { return record_archive(cache, key, compiles, bytes, inputs, stamps.get(), tables); },
               [&err](const std::string& warning) {
                 if (!warning.empty())
                   err << "statepack: warning: --cache-dir: " << printable(warning) << "\n";
               });
}

// Every file the pack read (the notation's and each compile's, #includes too): no output may replace one.
std::vector<InputFile> files_read_by(const Notation& notation, const CompiledShaders& compiled,
                                     const CompiledShaders& gl_compiled) {
  std::vector<InputFile> inputs = notation.files_read;
  for (const auto* c : {&compiled, &gl_compiled})
    for (const auto& u : c->units)
      inputs.insert(inputs.end(), u.compiled.files_read.begin(), u.compiled.files_read.end());
  return inputs;
}

// Every notation file given, read into one notation, its references resolved.
Notation read_notations(const PackOptions& options, Diagnostics& diag) {
  Notation notation;
  for (const auto& input : options.inputs) read_notation(input, options.notation, notation, diag);
  resolve_references(notation, diag);
  return notation;
}

// A notation that defines nothing makes an empty archive: said, as it is seldom meant.
void note_if_empty(const Notation& notation, const PackOptions& options, Diagnostics& diag) {
  if (notation.pipelines.empty() && notation.shaders.empty() && notation.signatures.empty() &&
      notation.render_passes.empty() && !diag.has_errors())
    diag.note({options.inputs.empty() ? "" : options.inputs.front().string()},
              "no pipelines, shaders, signatures or render passes: the archive is empty");
}

// The pack's --watch memory (repack_memo.hpp), with what no longer holds dropped; nullptr outside a
// session. The cache's bundle saves opening entry files; in a session whose memory holds the compiles it
// would be read (megabytes hashed) for the few shaders that changed, so after the first pack it is left
// alone, neither read nor rewritten: the next one-shot pack finds it as the session's first pack left it.
RepackMemo* bundle_and_memo(const PackOptions& options, PackSession* session,
                            std::optional<CompileCache>& cache, PhaseTimes& times) {
  RepackMemo* const memo = session ? session->memo : nullptr;
  if (cache && !(memo && memo->units_held() > 0)) cache->use_bundle(bundle_project(options));
  if (memo) {
    times.done("open the cache");
    memo->refresh(options);
    times.done("check what the last pack left");
  }
  return memo;
}

// The OpenGL units, made from the Vulkan compile; --opengl alone is warned that it stores pipelines only.
CompiledShaders opengl_compile(const Notation& notation, const CompiledShaders& compiled,
                               const PackOptions& options, Diagnostics& diag, CompileCache* cache) {
  CompiledShaders gl = opengl_units(compiled, options, diag, cache);
  if (!options.vulkan &&
      (!notation.shaders.empty() || !notation.signatures.empty() || !notation.render_passes.empty()))
    diag.warning(
        {options.inputs.empty() ? "" : options.inputs.front().string()},
        "--opengl alone stores pipelines only: the notation's standalone Shaders, resource "
        "signatures and render passes are Vulkan objects and are left out (add --vulkan to keep them)");
  return gl;
}

// The notation: a --watch session's last one when it still holds (repack_memo.hpp), else read.
struct PackNotation {
  std::shared_ptr<const Notation> notation;
  bool keepable = false;  // read without a message: the memo may hold it (taking it prints nothing either)
};
PackNotation held_or_read_notation(const PackOptions& options, const RepackMemo* memo, Diagnostics& diag,
                                   PhaseTimes& times) {
  if (memo)
    if (auto held = memo->notation()) {
      times.done("read notation (unchanged since the last pack: kept)");
      return {std::move(held), true};
    }
  auto read = std::make_shared<const Notation>(read_notations(options, diag));
  times.done("read notation");
  return {std::move(read), diag.all().empty()};
}

// What this pack read and made, for the next pack of the --watch session (repack_memo.hpp).
void keep_for_next_pack(RepackMemo& memo, const PackNotation& notation, const ArchiveKey* record,
                        const CompiledShaders& compiled, const Finalizer& finalizer,
                        const PackOptions& options, std::chrono::system_clock::time_point started) {
  RepackMemo::Made made;
  if (notation.keepable) made.notation = notation.notation;
  made.texts = record ? &record->shader_texts : nullptr;
  for (size_t i = 0; i < compiled.units.size(); ++i) {
    const CompiledUnit& u = compiled.units[i];
    if (u.compiled.ok)
      made.units.push_back({&compiled.unit_keys[i], u.held, &u.desc, &u.compiled, &u.reflection, &u.module});
  }
  made.finalized = finalizer.made();
  memo.keep(made, started, options.compile);
}

}  // namespace

std::optional<int> pack_if_unchanged(const PackOptions& options, std::ostream& out, std::ostream& err) {
  if (!options.cache_dir || !options.archive_reuse || options.dump_dir || options.shards ||
      options.notation.memory_files || !output_refusal(options).empty())
    return std::nullopt;
  PhaseTimes times(options.time_report ? &err : nullptr);
  std::string error;
  auto cache = CompileCache::open(*options.cache_dir, options.cache_max_bytes, error);
  if (!cache) return std::nullopt;
  cache->set_signing_key(options.cache_signing_key);
  std::vector<InputFile> inputs;
  const auto archive = find_unchanged_archive(*cache, options, bundle_project(options), inputs);
  if (!archive) return std::nullopt;
  return write_reused(options, archive->bytes, inputs, nullptr, times, out, err, true);
}

int run_pack(const PackOptions& options, std::ostream& out, std::ostream& err, PackSession* session) {
  const auto started = std::chrono::system_clock::now();  // (before anything is read: input_stamps.hpp)
  PhaseTimes times(options.time_report ? &err : nullptr);
  if (session) session->files_read.clear();
  if (std::string reason = output_refusal(options); !reason.empty()) {
    err << "statepack: error: " << printable(reason) << '\n';
    return kExitUsage;
  }
  PackCache pack_cache;
  open_cache(options, session, pack_cache, err);
  CompileCache* const cached = pack_cache.cache;
  const auto& remote = pack_cache.remote;
  std::optional<CompileCache>& cache = pack_cache.owned;
  if (options.shards && !cached) {  // (--cache-dir could not be opened, and no server was given)
    err << "statepack: error: --shard compiles into the caches, and there is none to write to\n";
    return kExitIoError;
  }
  CompilerWarmup warmup;  // (joined when the pack ends; before the stats: it reads the input stamps)
  warmup.start_early(options, cached, bundle_project(options));
  const CompileCache::Stats stats_before = cached ? cached->stats() : CompileCache::Stats{};
  RepackMemo* const memo = bundle_and_memo(options, session, cache, times);
  Diagnostics diag(options.max_errors);
  const PackNotation read = held_or_read_notation(options, memo, diag, times);
  const Notation& notation = *read.notation;
  warmup.start(notation, options, cached, bundle_project(options));
  const std::optional<ArchiveKey> record = archive_record_key(options, session, cached, notation, diag);
  // (a --watch session's first pack makes its archive, so that the session's memory holds its compiles)
  if (record && !(memo && !memo->filled()))
    if (auto code = reuse_archive(options, *cached, *record, notation, session, times, out, err, started))
      return *code;
  note_if_empty(notation, options, diag);
  // Layouts and pipelines are planned only from an error-free notation; shaders compile regardless.
  const bool notation_ok = !diag.has_errors();
  // OpenGL is made from the Vulkan compile (translated, or checked against it), so --opengl alone
  // compiles the pipelines' shaders for Vulkan too.
  CompiledShaders compiled, gl_compiled;
  if (options.vulkan || options.opengl)
    compiled =
        compile_shaders(notation, options, diag, !options.vulkan, cached, record ? &*record : nullptr, memo);
  times.done("compile");
  if (options.time_report)
    if (std::string built = warmup.report(); !built.empty()) times.note(built);
  if (options.opengl) gl_compiled = opengl_compile(notation, compiled, options, diag, cached);
  const std::vector<InputFile> inputs = files_read_by(notation, compiled, gl_compiled);
  if (session)
    for (const auto& f : inputs) session->files_read.push_back(f.path);
  StampsAhead stamps;  // (only for a record: a --shard pack has none)
  if (record) stamps.start(notation.lookups, inputs, started);
  if (options.shards)
    return finish_shard(options, compiled, *cached, stats_before, inputs, remote.get(), times, diag, out,
                        err);

  ContentsBuilder builder;
  builder.contents.producer_version = kProducerVersion;
  builder.contents.content_version = options.content_version;
  builder.contents.backends =
      (options.vulkan ? format::kBackendVulkan : 0u) | (options.opengl ? format::kBackendOpenGL : 0u);
  Finalizer finalizer(options.compile, cached, memo);
  Dumper dumper(options.dump_dir, options.compile, inputs);
  std::string io_error;
  if (notation_ok && options.vulkan) {
    Plan plan = plan_archive(notation, compiled, {options.strict}, builder, finalizer, diag);
    times.done("lay out and check");
    finalizer.run(options.threads);  // optimise and validate every distinct module in parallel
    times.done("optimise and validate");
    assemble_archive(notation, compiled, plan, finalizer, builder, dumper, io_error, diag);
    times.done("assemble");
  }
  if (notation_ok && options.opengl) add_opengl(notation, gl_compiled, options, builder, diag, cached);
  // What compiled is kept whether or not the pack succeeds: the next run needs it either way.
  ReportedThread flushing;
  flush_in_background(flushing, cached, stats_before, inputs, remote.get(), times, err);
  if (!diag.has_errors()) note_unused_objects(notation, diag);
  if (diag.has_errors()) {
    diag.print(err);
    err << "statepack: " << diag.error_count() << " error(s); no archive written\n";
    return kExitInputError;
  }
  diag.print(err);  // warnings
  if (!io_error.empty()) {
    err << "statepack: error: " << printable(io_error) << '\n';
    return kExitIoError;
  }

  std::vector<uint8_t> bytes = format::encode(builder.contents);
  times.done("encode");
  // What pack writes must load: decoded and checked against its SPIR-V as the runtime will, so a build
  // step that says OK means it (a check the pack stages missed surfaces here, not in the application).
  if (auto loads = format::load_archive_with_opengl(bytes, std::nullopt, "the packed archive would not load",
                                                    options.threads);
      !loads) {
    std::string message = loads.error().message;
    if (auto at = message.find("corrupt archive: "); at != std::string::npos) message.erase(at, 17);
    err << "statepack: error: " << printable(message) << "; no archive written\n";
    return kExitInputError;
  }
  times.done("load-back check");
  flushing.finish();
  // Only a pack that printed nothing is recorded: a reuse prints nothing either.
  const bool recorded = record && diag.all().empty();
  ReportedThread recording;
  if (recorded)
    record_in_background(recording, *cached, *record, compiled, gl_compiled, inputs, stamps,
                         tables_hint(notation, options.compile), bytes, err);
  if (!options.check_only)
    if (int code = write_outputs(options, inputs, bytes, err); code != kExitSuccess) return code;
  times.done("write");
  if (recorded) {
    recording.finish();
    times.done("record the archive");
  }
  if (memo) {
    keep_for_next_pack(*memo, read, record ? &*record : nullptr, compiled, finalizer, options, started);
    times.done("keep for the next pack");
  }
  return options.print_contents ? print_written(bytes, out, err) : kExitSuccess;
}

}  // namespace statepack::packager
