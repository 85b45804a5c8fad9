#include "repack_memo.hpp"

#include <algorithm>
#include <set>
#include <span>

#include "format/archive_format.hpp"

namespace statepack::packager {

namespace fs = std::filesystem;

uint64_t module_hash(const std::vector<uint32_t>& words, bool optimize) {
  return format::hash_bytes({reinterpret_cast<const uint8_t*>(words.data()), words.size() * 4}) ^
         (optimize ? 0 : 0x9e3779b97f4a7c15ull);
}

bool RepackMemo::stamp(const fs::path& path, const detail::FileIdentity& identity,
                       std::map<fs::path, FileState>& files, const RacyWindow& window) {
  if (auto known = files.find(path); known != files.end()) return known->second.holds;
  if (auto held = files_.find(path);
      held != files_.end() && held->second.holds &&
      detail::FileIdentity{held->second.stamp.device, held->second.stamp.inode} == identity) {
    files.emplace(path, held->second);
    return true;
  }
  const auto now = stamp_of(path);
  const bool trusted =
      now && window.trusts(*now) && detail::FileIdentity{now->device, now->inode} == identity;
  files.emplace(path, FileState{now.value_or(FileStamp{}), trusted});
  return trusted;
}

bool RepackMemo::stamp_lookups(const Notation& notation, std::map<fs::path, FileState>& files,
                               const RacyWindow& window) {
  std::set<detail::FileIdentity> read;
  for (const InputFile& f : notation.files_read) read.insert(f.identity);
  for (const FileLookup& l : notation.lookups) {
    if (l.shader) continue;  // (a shader file is stamped, through its link, with its text and compile)
    const auto now = stamp_of(l.found);
    if (!now || !window.trusts(*now) || !read.count(detail::FileIdentity{now->device, now->inode}))
      return false;
    files.insert_or_assign(l.found, FileState{*now, true});
    notation_files_.push_back(l.found);
  }
  return true;
}

bool RepackMemo::holds(const fs::path& path) const {
  auto it = files_.find(path);
  return it != files_.end() && it->second.holds;
}

bool RepackMemo::all_hold(const std::vector<fs::path>& paths) const {
  return std::ranges::all_of(paths, [&](const fs::path& path) { return holds(path); });
}

void RepackMemo::refresh(const PackOptions& options) {
  for (auto& [path, state] : files_)
    if (state.holds) state.holds = stamp_of(path) == state.stamp;
  if (notation_) {
    if (!all_hold(notation_files_) || !std::ranges::all_of(notation_->lookups, [&](const FileLookup& l) {
          return lookup_finds_the_same(l, options.notation);
        }))
      notation_.reset();
  }
  std::erase_if(texts_, [&](const auto& entry) { return !holds(entry.first); });
  std::erase_if(units_, [&](const auto& entry) {
    return !all_hold(entry.second.files) ||
           !std::ranges::all_of(entry.second.unit->compiled.includes, [&](const IncludeRecord& rec) {
             return include_found_again(rec, options.compile).has_value();
           });
  });
}

const CompileCache::KnownText* RepackMemo::text(const fs::path& path) const {
  auto it = texts_.find(path);
  return it == texts_.end() ? nullptr : &it->second;
}

std::shared_ptr<const RepackMemo::Unit> RepackMemo::unit(const std::string& unit_key) const {
  auto it = units_.find(unit_key);
  return it == units_.end() ? nullptr : it->second.unit;
}

std::shared_ptr<const RepackMemo::Finalized> RepackMemo::finalized(const std::vector<uint32_t>& input,
                                                                   bool optimize) const {
  auto [first, last] = finalized_.equal_range(module_hash(input, optimize));
  for (auto it = first; it != last; ++it)
    if (it->second->optimize == optimize && it->second->input == input) return it->second;
  return nullptr;
}

void RepackMemo::keep(const Made& made, std::chrono::system_clock::time_point started,
                      const CompileOptions& options) {
  const RacyWindow window(started);
  std::map<fs::path, FileState> files;
  std::shared_ptr<const Notation> notation = made.notation;
  notation_files_.clear();
  if (notation) {
    for (const InputFile& f : notation->files_read) {
      if (!stamp(f.path, f.identity, files, window)) notation.reset();
      notation_files_.push_back(f.path);
    }
    if (notation && !stamp_lookups(*notation, files, window)) notation.reset();
  }
  std::map<fs::path, CompileCache::KnownText> texts;
  if (made.texts)
    for (const auto& [path, text] : *made.texts)
      if (stamp(path, text.file.identity, files, window)) texts.emplace(path, text);
  std::map<std::string, UnitEntry> units;
  for (const Made::MadeUnit& made_unit : made.units) {
    const CompiledShader& compiled = made_unit.held ? made_unit.held->compiled : *made_unit.compiled;
    bool trusted = true;
    std::vector<fs::path> paths;
    for (const InputFile& f : compiled.files_read) {
      trusted = trusted && stamp(f.path, f.identity, files, window);
      paths.push_back(f.path);
    }
    if (!trusted) continue;
    auto unit = made_unit.held;
    if (!unit)
      unit = std::make_shared<const Unit>(
          Unit{compiled, *made_unit.reflection, *made_unit.module,
               compile_entry_key(*made_unit.desc, options, compiled.source_hash)});
    units.emplace(*made_unit.key, UnitEntry{std::move(unit), std::move(paths)});
  }
  // A module finalised again keeps its entry's key; a new one's is hashed once, here.
  CompileOptions unoptimized = options;
  unoptimized.optimization = Optimization::none;
  std::multimap<uint64_t, std::shared_ptr<const Finalized>> modules;
  for (const Made::MadeModule& f : made.finalized) {
    auto module = f.held;
    if (!module)
      module = std::make_shared<const Finalized>(
          Finalized{*f.input, f.optimize, *f.output,
                    finalized_entry_key(*f.input, f.optimize ? options : unoptimized)});
    modules.emplace(module_hash(module->input, module->optimize), std::move(module));
  }
  files_ = std::move(files);
  notation_ = std::move(notation);
  texts_ = std::move(texts);
  units_ = std::move(units);
  finalized_ = std::move(modules);
  filled_ = true;
}

}  // namespace statepack::packager
