#include "compiler_warmup.hpp"

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

CompilerWarmup::~CompilerWarmup() {
  if (thread_.joinable()) thread_.join();
}

void CompilerWarmup::start(const Notation& notation, const PackOptions& options, const CompileCache* cache,
                           std::string_view project) {
  if (!cache || !options.archive_reuse || options.threads == 1 || std::thread::hardware_concurrency() < 2)
    return;
  const ShaderDesc* shader = likely_compile(notation, cache->local_time(archive_slot(project)));
  if (!shader) return;
  // Copies: the pack goes on with its notation and options meanwhile. A speed-up only: when the copy or
  // the thread cannot be made, or the work throws (out of memory: the compile meets it too, and says so),
  // the pack goes on without it.
  try {
    thread_ = std::thread([shader = *shader, compile = options.compile] {
      try {
        prepare_compiler(shader, compile);
      } catch (...) {
      }
    });
  } catch (...) {
  }
}

}  // namespace statepack::packager
