#include "compiler_warmup.hpp"

#include <chrono>
#include <sstream>

#include "pack/archive_reuse.hpp"
#include "shaders/shader_compiler.hpp"

namespace statepack::packager {

namespace fs = std::filesystem;

const ShaderDesc* likely_compile(const Notation& notation,
                                 const std::optional<fs::file_time_type>& recorded) {
  auto changed = [&](const fs::path& path) {
    std::error_code ec;
    const auto time = fs::last_write_time(path, ec);
    return ec || time > *recorded;
  };
  bool any = !recorded;
  if (recorded)
    for (const auto& f : notation.files_read)
      if (changed(f.path)) {
        any = true;
        break;
      }
  const ShaderDesc* first = nullptr;
  auto consider = [&](const ShaderDesc& s) {
    if (s.is_reference || s.broken || s.language == SourceLanguage::spirv) return false;
    if (!first) first = &s;
    return any || (!s.file.empty() && changed(s.file));
  };
  for (const auto& p : notation.pipelines)
    for (const auto& s : p.shaders)
      if (consider(s)) return any ? first : &s;
  for (const auto& s : notation.shaders)
    if (consider(s)) return any ? first : &s;
  return nullptr;
}

namespace {
// What picks glslang's built-in tables for `shader` (and its stage).
TablesHint hint_of(const ShaderDesc& shader, const CompileOptions& options) {
  return TablesHint{shader.language, shader.stage, shader.glsl_version, tables_version_line(shader, options)};
}
}  // namespace

std::optional<TablesHint> tables_hint(const Notation& notation, const CompileOptions& options) {
  const ShaderDesc* first = likely_compile(notation, std::nullopt);
  if (!first) return std::nullopt;
  return hint_of(*first, options);
}

void CompilerWarmup::build(const ShaderDesc& shader, const CompileOptions& options, std::atomic<double>& ms) {
  const auto begun = std::chrono::steady_clock::now();
  prepare_compiler(shader, options);
  ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - begun).count();
}

std::string CompilerWarmup::report() const {
  std::string out;
  auto line = [&](bool building, const std::atomic<double>& ms, const char* hint) {
    if (!building) return;
    if (!out.empty()) out += '\n';
    out += std::string("compiler: glslang's built-in tables built ahead on another core, from ") + hint;
    std::ostringstream took;  // (as PhaseTimes prints a time)
    if (const double done = ms; done < 0)
      took << " (still building)";
    else
      took << " (" << done << " ms)";
    out += took.str();
  };
  // (The early thread builds only once it found a stamped file changed: until then, nothing to say.)
  line(early_.joinable() && early_building_, early_ms_, "the input stamps' hint");
  line(late_.joinable(), late_ms_, "the notation's likely compile");
  return out;
}

CompilerWarmup::~CompilerWarmup() {
  for (std::thread* t : {&early_, &late_})
    if (t->joinable()) t->join();
}

bool CompilerWarmup::wanted(const PackOptions& options, const CompileCache* cache) {
  return cache && options.archive_reuse && options.threads != 1 && std::thread::hardware_concurrency() >= 2;
}

void CompilerWarmup::start_early(const PackOptions& options, CompileCache* cache, std::string_view project) {
  if (!wanted(options, cache)) return;
  auto stamps = cache->find_local(stamps_slot(archive_slot(project)));
  if (!stamps) return;
  early_hint_ = stamped_hint(stamps->payload);
  if (!early_hint_) return;
  // The entry (mapped) goes with the thread, which stats the stamped files (about 1 µs each) and then
  // builds the tables while this one reads the notation. As with start(), a speed-up only.
  try {
    early_ = std::thread([this, stamps = std::move(*stamps), compile = options.compile] {
      try {
        if (!hint_if_changed(stamps.payload)) {
          early_found_nothing_ = true;
          return;
        }
        ShaderDesc shader;
        shader.language = early_hint_->language, shader.stage = early_hint_->stage;
        shader.glsl_version = early_hint_->glsl_version, shader.source = early_hint_->version_line;
        early_building_ = true;
        build(shader, compile, early_ms_);
      } catch (...) {
      }
    });
  } catch (...) {
  }
}

void CompilerWarmup::start(const Notation& notation, const PackOptions& options, const CompileCache* cache,
                           std::string_view project) {
  if (!wanted(options, cache)) return;
  const ShaderDesc* shader = likely_compile(notation, cache->local_time(archive_slot(project)));
  if (!shader) return;
  if (early_.joinable() && !early_found_nothing_) {
    TablesHint likely = hint_of(*shader, options.compile);
    likely.stage = early_hint_->stage;  // (the stage does not pick the tables: glslang builds every stage's)
    if (likely == *early_hint_) return;
  }
  // Copies: the pack goes on with its notation and options meanwhile. A speed-up only: when the copy or
  // the thread cannot be made, or the work throws (out of memory: the compile meets it too, and says so),
  // the pack goes on without it.
  try {
    late_ = std::thread([this, shader = *shader, compile = options.compile] {
      try {
        build(shader, compile, late_ms_);
      } catch (...) {
      }
    });
  } catch (...) {
  }
}

}  // namespace statepack::packager
