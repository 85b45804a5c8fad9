#include "archive_reuse.hpp"

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

std::optional<ArchiveKey> archive_key(const PackOptions& options, std::string_view project,
                                      const Notation& notation, const Diagnostics& diagnostics) {
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
    if (!seen.insert(unit_key(s)).second) return true;
    InputFile file;
    Digest text{};
    const auto key = compile_cache_key(s, options.compile, &file, &text);
    if (!key) return false;
    k.add(*key);
    if (!file.path.empty()) {
      out.shader_texts.emplace(file.path, text);
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
  out.slot = KeyBuilder().add("archive record").add(code_identity()).add(project).key();
  return out;
}

std::optional<RecordedArchive> find_archive(CompileCache& cache, const ArchiveKey& key,
                                            const CompileOptions& options,
                                            std::vector<InputFile>& files_read) {
  const auto entry = cache.find_local(key.slot);
  if (!entry) return std::nullopt;
  PayloadReader r(entry->payload);
  uint32_t version = 0, count = 0;
  CacheKey made_from{};
  if (!r.u32(version) || version != kRecordVersion || !r.raw(made_from.data(), made_from.size()) ||
      made_from != key.inputs || !r.u32(count) || !r.room_for(count, 45))
    return std::nullopt;
  std::vector<InputFile> includes;
  IncludeTexts texts;  // (an #include that many shaders share is read once)
  for (uint32_t i = 0; i < count; ++i) {
    IncludeRecord rec;
    uint64_t included = 0;  // (each within the bound alone: the compiles that made the record were)
    if (!read_include_record(r, rec)) return std::nullopt;
    auto file = include_still_holds(rec, options, included, &texts);
    if (!file) return std::nullopt;
    includes.push_back(std::move(*file));
  }
  uint32_t low = 0, high = 0;
  if (!r.u32(low) || !r.u32(high)) return std::nullopt;
  uint8_t padding[kArchiveAlignment];
  const size_t at = entry->payload.size() - r.left();
  if (!r.raw(padding, (kArchiveAlignment - at % kArchiveAlignment) % kArchiveAlignment)) return std::nullopt;
  const uint64_t size = uint64_t(high) << 32 | low;
  if (size != r.left()) return std::nullopt;
  files_read.insert(files_read.end(), key.shader_files.begin(), key.shader_files.end());
  files_read.insert(files_read.end(), includes.begin(), includes.end());
  return RecordedArchive{entry->holder, entry->payload.last(r.left())};
}

std::string record_archive(CompileCache& cache, const ArchiveKey& key,
                           const std::vector<const CompiledShader*>& compiles,
                           std::span<const uint8_t> archive, const std::vector<InputFile>& inputs) {
  for (const CompiledShader* c : compiles)
    if (!c->files_read.empty())
      if (auto hashed = key.shader_texts.find(c->files_read.front().path);
          hashed != key.shader_texts.end() && hashed->second != c->source_hash)
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
  w.u32(uint32_t(archive.size()));
  w.u32(uint32_t(uint64_t(archive.size()) >> 32));
  w.bytes.resize((w.bytes.size() + kArchiveAlignment - 1) / kArchiveAlignment * kArchiveAlignment);
  return cache.store_local(key.slot, w.bytes, archive, inputs);
}

}  // namespace statepack::packager
