#include "archive_reuse.hpp"

#include "pack/input_stamps.hpp"
#include "pack/repack_memo.hpp"

#include <set>
#include <tuple>

namespace statepack::packager {
namespace {

constexpr uint32_t kRecordVersion = 2;
constexpr size_t kArchiveAlignment = 16;

void add_paths(KeyBuilder& k, const std::vector<std::filesystem::path>& paths) {
  k.add(uint64_t(paths.size()));
  for (const auto& p : paths) k.add(display_path(p));
}

// The options that decide the archive's bytes (not --threads, --check, --print-contents, the output's
// name, the cache's own settings: none of them changes a byte).
void add_options(KeyBuilder& k, const PackOptions& options) {
  const CompileOptions& c = options.compile;
  k.add(uint64_t(options.content_version)).add(uint64_t(options.vulkan)).add(uint64_t(options.opengl));
  k.add(uint64_t(options.strict));
  add_paths(k, c.include_dirs);
  k.add(uint64_t(c.global_macros.size()));
  for (const auto& [name, value] : c.global_macros) k.add(name).add(value);
  k.add(uint64_t(c.vulkan_version)).add(uint64_t(c.optimization)).add(uint64_t(c.strip_debug_info));
  k.add(uint64_t(c.opengl)).add(uint64_t(c.shader_environment)).add(c.max_input_bytes);
  add_paths(k, options.notation.render_state_dirs);
  add_paths(k, options.notation.shader_dirs);
  k.add(options.notation.max_input_bytes);
}

}  // namespace

CacheKey record_id(std::span<const uint8_t> header) {
  return KeyBuilder()
      .add("archive record id")
      .add(std::string_view(reinterpret_cast<const char*>(header.data()), header.size()))
      .key();
}

CacheKey setup_key(const PackOptions& options) {
  KeyBuilder k;
  k.add("archive setup").add(uint64_t(kRecordVersion)).add(code_identity());
  add_options(k, options);
  return k.key();
}

CacheKey archive_slot(std::string_view project) {
  return KeyBuilder().add("archive record").add(code_identity()).add(project).key();
}

std::optional<ArchiveKey> archive_key(const PackOptions& options, std::string_view project,
                                      const Notation& notation, const Diagnostics& diagnostics,
                                      const RepackMemo* memo) {
  if (options.dump_dir || options.shards || options.notation.memory_files || !diagnostics.all().empty())
    return std::nullopt;
  ArchiveKey out;
  KeyBuilder k;
  k.add("archive").add(uint64_t(kRecordVersion)).add(code_identity());
  add_options(k, options);
  const auto texts = notation.sources.all();
  k.add(uint64_t(texts.size()));
  for (const auto& [name, text] : texts) k.add(name).add(sha256(text));
  // Every shader the pack compiles, as compile_shaders() walks them, each distinct one once.
  std::set<std::string> seen;
  auto add_shader = [&](const ShaderDesc& s) {
    const auto [unit, first] = seen.insert(unit_key(s));
    if (!first) return true;
    InputFile file;
    Digest text{};
    const CompileCache::KnownText* known =
        memo && !s.file.empty() ? memo->text((working_directory() / s.file).lexically_normal()) : nullptr;
    std::optional<CacheKey> key;
    if (known) {
      file = known->file;
      text = known->hash;
      // A compile the memo holds of the same text: its entry's key is this key.
      const auto held = memo->unit(*unit);
      key = held && held->compiled.source_hash == known->hash ? held->entry
                                                              : compile_cache_key(s, options.compile, *known);
    } else {
      key = compile_cache_key(s, options.compile, &file, &text);
    }
    if (!key) return false;
    k.add(*key);
    if (!file.path.empty()) {
      // A file read twice (two shaders of it) and saved in between: no record of either text.
      if (auto [at, added] = out.shader_texts.emplace(file.path, CompileCache::KnownText{file, text});
          !added && at->second.hash != text)
        return false;
      out.shader_files.push_back(std::move(file));
    }
    return true;
  };
  for (const auto& p : notation.pipelines)
    for (const auto& s : p.shaders)
      if (!s.is_reference && !add_shader(s)) return std::nullopt;
  for (const auto& s : notation.shaders)
    if (!add_shader(s)) return std::nullopt;
  out.inputs = k.key();
  out.slot = archive_slot(project);
  out.setup = setup_key(options);
  return out;
}

namespace {

// A record's parts (archive_reuse.hpp's table); nullopt when it is not a record this version reads.
struct RecordParts {
  CacheKey inputs{};
  std::vector<IncludeRecord> includes;
  std::span<const uint8_t> archive;
  CacheKey id{};  // record_id of the payload before the archive
};
std::optional<RecordParts> read_record(std::span<const uint8_t> payload) {
  PayloadReader r(payload);
  RecordParts out;
  uint32_t version = 0, count = 0;
  if (!r.u32(version) || version != kRecordVersion || !r.raw(out.inputs.data(), out.inputs.size()) ||
      !r.u32(count) || !r.room_for(count, 45))
    return std::nullopt;
  out.includes.resize(count);
  for (IncludeRecord& rec : out.includes)
    if (!read_include_record(r, rec)) return std::nullopt;
  uint64_t size = 0;
  if (!r.u64(size)) return std::nullopt;
  uint8_t padding[kArchiveAlignment];
  const size_t at = payload.size() - r.left();
  if (!r.raw(padding, (kArchiveAlignment - at % kArchiveAlignment) % kArchiveAlignment)) return std::nullopt;
  if (size != r.left()) return std::nullopt;
  out.archive = payload.last(r.left());
  out.id = record_id(payload.first(payload.size() - out.archive.size()));
  return out;
}

}  // namespace

std::optional<RecordedArchive> find_archive(CompileCache& cache, const ArchiveKey& key,
                                            const CompileOptions& options,
                                            std::vector<InputFile>& files_read) {
  const auto entry = cache.find_local(key.slot);
  if (!entry) return std::nullopt;
  const auto parts = read_record(entry->payload);
  if (!parts || parts->inputs != key.inputs) return std::nullopt;
  std::vector<InputFile> includes;
  IncludeTexts texts;  // (an #include that many shaders share is read once)
  for (const IncludeRecord& rec : parts->includes) {
    uint64_t included = 0;  // (each within the bound alone: the compiles that made the record were)
    auto file = include_still_holds(rec, options, included, &texts);
    if (!file) return std::nullopt;
    includes.push_back(std::move(*file));
  }
  files_read.insert(files_read.end(), key.shader_files.begin(), key.shader_files.end());
  files_read.insert(files_read.end(), includes.begin(), includes.end());
  return RecordedArchive{entry->holder, parts->archive, parts->id};
}

std::optional<RecordedArchive> find_unchanged_archive(CompileCache& cache, const PackOptions& options,
                                                      std::string_view project,
                                                      std::vector<InputFile>& files_read) {
  const CacheKey slot = archive_slot(project);
  const auto stamped = unchanged_inputs(cache, slot, setup_key(options), options.notation);
  if (!stamped) return std::nullopt;
  const auto entry = cache.find_local(slot);
  if (!entry) return std::nullopt;
  const auto parts = read_record(entry->payload);
  // The very record the stamps were written for: another one (written later by a pack that read other
  // #include texts, or whose own record was not kept) is not vouched for.
  if (!parts || parts->id != stamped->record) return std::nullopt;
  // Each #include found where it was, and stamped: the record may have been written after the stamps by
  // a pack that found an #include elsewhere (the inputs key leaves #includes out), whose bytes the stamps
  // then do not vouch for.
  std::set<std::filesystem::path> stamped_paths;
  for (const InputFile& f : stamped->files) stamped_paths.insert(f.path);
  for (const IncludeRecord& rec : parts->includes) {
    const auto path = include_found_again(rec, options.compile);
    if (!path || !stamped_paths.count((working_directory() / *path).lexically_normal())) return std::nullopt;
  }
  files_read = stamped->files;
  return RecordedArchive{entry->holder, parts->archive, stamped->record};
}

std::string record_archive(CompileCache& cache, const ArchiveKey& key,
                           const std::vector<const CompiledShader*>& compiles,
                           std::span<const uint8_t> archive, const std::vector<InputFile>& inputs,
                           const std::optional<TakenStamps>& stamps,
                           const std::optional<TablesHint>& tables) {
  for (const CompiledShader* c : compiles)
    if (!c->files_read.empty())
      if (auto hashed = key.shader_texts.find(c->files_read.front().path);
          hashed != key.shader_texts.end() && hashed->second.hash != c->source_hash)
        return "";  // saved while the pack ran: the next pack makes (and records) it again
  PayloadWriter w;
  w.u32(kRecordVersion);
  w.bytes.insert(w.bytes.end(), key.inputs.begin(), key.inputs.end());
  std::vector<const IncludeRecord*> records;
  std::set<std::tuple<std::string_view, std::string_view, bool, std::string_view>> seen;
  for (const CompiledShader* c : compiles)
    for (const IncludeRecord& rec : c->includes)
      if (seen.emplace(rec.header, rec.includer, rec.local, rec.path).second) records.push_back(&rec);
  w.u32(uint32_t(records.size()));
  for (const IncludeRecord* rec : records) write_include_record(w, *rec);
  w.u64(archive.size());
  w.bytes.resize((w.bytes.size() + kArchiveAlignment - 1) / kArchiveAlignment * kArchiveAlignment);
  if (std::string warning = cache.store_local(key.slot, w.bytes, archive, inputs); !warning.empty())
    return warning;
  if (!stamps) return "";
  return store_input_stamps(cache, key.slot, {record_id(w.bytes), key.setup, {}, inputs, tables}, *stamps);
}

}  // namespace statepack::packager
