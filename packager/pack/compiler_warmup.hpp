#pragma once
// glslang's built-in tables built ahead. Before its first compile glslang builds the symbol tables of
// every stage for the shader's #version (~50 ms, once per process, serial under glslang's own lock); in a
// repack after one shader changed that was the longest stage, while the second core waited. A pack that
// will likely compile builds them on another core while it hashes its inputs and looks them up in the
// cache (prepare_compiler); a repack that changed nothing compiles nothing and builds nothing.
#include <atomic>
#include <optional>
#include <string>
#include <thread>

#include "notation/notation.hpp"
#include "pack/input_stamps.hpp"
#include "pack/packer.hpp"
#include "shaders/compile_cache.hpp"

namespace statepack::packager {

// The shader a pack will likely compile first: with the project's archive record written at `recorded`,
// the first whose file changed after it, or the first of all when a notation file did; nullptr when
// nothing did (an #include is not looked at: a miss then only compiles without a head start). Without a
// record, the first shader. Shaders given as SPIR-V compile nothing.
const ShaderDesc* likely_compile(const Notation& notation,
                                 const std::optional<std::filesystem::file_time_type>& recorded);

// What picks glslang's tables for the notation's first shader that compiles from source (its language,
// stage, GLSLVersion and #version line, read from its file), for the input stamps; nullopt when there
// is none.
std::optional<TablesHint> tables_hint(const Notation& notation, const CompileOptions& options);

// Runs prepare_compiler on a thread of its own, joined when this object ends (the pack's end).
class CompilerWarmup {
 public:
  CompilerWarmup() = default;
  CompilerWarmup(const CompilerWarmup&) = delete;
  CompilerWarmup& operator=(const CompilerWarmup&) = delete;
  ~CompilerWarmup();
  // As the pack starts, before its notation is read: from the input stamps' tables hint, when one of
  // the stamped files changed (input_stamps.hpp). Both starts only with an archive record to compare
  // against (a cache, archive reuse on) and more than one thread.
  void start_early(const PackOptions& options, CompileCache* cache, std::string_view project);
  // Once the notation is read, for what this pack will likely compile, unless start_early builds the
  // same tables (it found a stamped file changed, or has not yet looked: a few ms against the notation
  // read's tens). A project whose changed shader needs other tables than its first gets both.
  void start(const Notation& notation, const PackOptions& options, const CompileCache* cache,
             std::string_view project);
  // For --time-report, once the pack's compiles are done: which tables were built ahead, from what hint,
  // and in how long (or that they still are); "" when none was started.
  std::string report() const;

 private:
  static bool wanted(const PackOptions& options, const CompileCache* cache);
  // Builds the tables for `shader` on this thread, and notes how long that took in `ms`.
  static void build(const ShaderDesc& shader, const CompileOptions& options, std::atomic<double>& ms);
  std::thread early_, late_;
  std::optional<TablesHint> early_hint_;
  std::atomic<bool> early_found_nothing_{false}, early_building_{false};
  std::atomic<double> early_ms_{-1}, late_ms_{-1};  // each build's wall time, once it is done
};

}  // namespace statepack::packager
