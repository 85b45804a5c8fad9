// What a --watch session keeps from one pack for the next (issue 39): a repack after one shader of a
// thousand changed read, hashed and looked up all thousand again, walked every module, and read the whole
// notation again; under --watch that cost about as much as a new process. The memo holds, from the last
// pack that wrote its archive:
// - its notation, when reading it printed nothing;
// - each shader file's text identity and hash (what the archive record's key and the compile lookups use);
// - each distinct shader's compile: SPIR-V, reflection and walked module, with the compile-cache entry it
//   stands for;
// - each finalised module (optimised, stripped, validated), by the module it was made from.
// Each holds only while what it came from still holds, checked as the next pack begins:
// - a file holds while it stats as it did when stamped (device, inode, size, modification and change times
//   to the nanosecond), and a stamp is trusted only when taken after the pack read the file, with both times
//   older than kRacyWindow before that pack began (input_stamps.hpp: the same rule, for the same reasons);
// - the notation holds while every notation file holds and every file name it looked up is found where it
//   was (a file that appears earlier in the search misses);
// - a compile holds while its shader file and each #include hold and each #include is found where it was;
// - a finalised module depends on nothing but the module and the options, which a session does not change.
// What does not hold is read, looked up and compiled as any pack does, so the archive is the same bytes as
// a clean pack's. A hit counts as the cache hit it replaces (CompileCache::note_used), so the cache's
// trimming and bundle see the entries the pack used.
#pragma once

#include <chrono>
#include <cstdint>
#include <filesystem>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "format/spirv_walk.hpp"
#include "notation/notation.hpp"
#include "pack/input_stamps.hpp"
#include "pack/packer.hpp"
#include "shaders/compile_cache.hpp"
#include "shaders/spirv_reflect.hpp"

namespace statepack::packager {

// XXH3 of a module to finalise, with whether it is optimised: how the memo and the pack's Finalizer find a
// module they have seen (then compared word by word: a collision must not merge modules).
uint64_t module_hash(const std::vector<uint32_t>& words, bool optimize);

class RepackMemo {
 public:
  struct Unit {
    CompiledShader compiled;
    Reflection reflection;
    std::optional<spirv::Module> module;
    CacheKey entry{};  // the compile-cache entry it stands for (compile_entry_key)
  };
  // A module finalised (optimised or not, stripped, validated): the module before and after, and the key
  // of the cache entry that holds it.
  struct Finalized {
    std::vector<uint32_t> input;
    bool optimize = true;
    std::vector<uint32_t> output;
    CacheKey entry{};
  };
  // What one pack leaves; `keep` takes it.
  struct Made {
    std::shared_ptr<const Notation> notation;  // null: read with a message, not kept
    const std::map<std::filesystem::path, CompileCache::KnownText>* texts = nullptr;
    struct MadeUnit {
      const std::string* key;            // unit_key
      std::shared_ptr<const Unit> held;  // what the memo gave the pack for it; else the parts below
      const ShaderDesc* desc;
      const CompiledShader* compiled;
      const Reflection* reflection;
      const std::optional<spirv::Module>* module;
    };
    std::vector<MadeUnit> units;  // compiles that passed every check only
    struct MadeModule {
      std::shared_ptr<const Finalized> held;  // what the memo gave the pack for it; else the parts below
      const std::vector<uint32_t>* input;
      bool optimize;
      const std::vector<uint32_t>* output;
    };
    std::vector<MadeModule> finalized;
  };

  // As a pack begins: drops whatever no longer holds (above).
  void refresh(const PackOptions& options);

  // The last pack's notation, when it still holds.
  std::shared_ptr<const Notation> notation() const { return notation_; }
  // A shader file's text as last read, when it still holds; nullptr otherwise.
  const CompileCache::KnownText* text(const std::filesystem::path& path) const;
  // The compile of the distinct shader `unit_key`, when it still holds; null otherwise.
  std::shared_ptr<const Unit> unit(const std::string& unit_key) const;
  // finalize_spirv's result for `input` (optimised or not), when the last pack made it; null otherwise.
  std::shared_ptr<const Finalized> finalized(const std::vector<uint32_t>& input, bool optimize) const;

  // After a pack that wrote its archive: what it read and made replaces what was kept. `started`: when
  // it began (its stamps are trusted only for files older than kRacyWindow before that); `options`: its
  // compile options (for the cache keys of what it finalised).
  void keep(const Made& made, std::chrono::system_clock::time_point started, const CompileOptions& options);

  // How many compiles it holds (those the last pack kept; after refresh(), those that still hold).
  size_t units_held() const { return units_.size(); }
  // Whether a pack has kept anything yet (a session's first pack fills it: it reuses no recorded archive).
  bool filled() const { return filled_; }

 private:
  struct FileState {
    FileStamp stamp;
    bool holds = true;
  };
  struct UnitEntry {
    std::shared_ptr<const Unit> unit;
    std::vector<std::filesystem::path> files;  // the shader file and its #includes
  };
  // Stamps `path` (read as `identity`) into `files`, when trusted (a file that still held at refresh()
  // keeps its stamp); whether it was.
  bool stamp(const std::filesystem::path& path, const detail::FileIdentity& identity,
             std::map<std::filesystem::path, FileState>& files, const RacyWindow& window);
  // Stamps what each name a notation lookup found leads to (a link followed), which must be a file the
  // notation read: a link given as -i and pointed elsewhere, or a name that was a second link to a file
  // read once and is now a file of its own, changes only that. Whether every one was trusted.
  bool stamp_lookups(const Notation& notation, std::map<std::filesystem::path, FileState>& files,
                     const RacyWindow& window);
  bool holds(const std::filesystem::path& path) const;
  bool all_hold(const std::vector<std::filesystem::path>& paths) const;

  std::map<std::filesystem::path, FileState> files_;
  std::shared_ptr<const Notation> notation_;
  std::vector<std::filesystem::path> notation_files_;  // its files and the names its lookups found
  std::map<std::filesystem::path, CompileCache::KnownText> texts_;
  std::map<std::string, UnitEntry> units_;
  std::multimap<uint64_t, std::shared_ptr<const Finalized>> finalized_;  // by XXH3 of the input module
  bool filled_ = false;
};

}  // namespace statepack::packager
