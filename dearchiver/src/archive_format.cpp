// statepack archive format v1: encoder and validating decoder.
//
// All integers are little-endian; strings are UTF-8. docs/archive-format.md is the full spec; the
// tables below are its summary, kept next to the code that reads them.
//
// Header (64 bytes at offset 0)
// | off | type   | field                                                                  |
// |-----|--------|------------------------------------------------------------------------|
// |   0 | u8[8]  | magic 89 'S' 'P' 'K' 0D 0A 1A 0A                                       |
// |   8 | u32    | format_version (1)                                                     |
// |  12 | u32    | oldest_readable_version: a reader older than this must refuse the file |
// |  16 | u32    | header_size (64)                                                       |
// |  20 | u32    | producer_version (major<<22 | minor<<12 | patch)                       |
// |  24 | u32    | content_version (user's, statepack -v)                                 |
// |  28 | u32    | backends (bit 0 vulkan, bit 1 opengl)                                  |
// |  32 | u64    | file_size                                                              |
// |  40 | u64    | checksum: XXH3-64 of the whole file with these 8 bytes read as zero    |
// |  48 | u32    | section_count                                                          |
// |  52 | u32    | section_table_offset (64)                                              |
// |  56 | u64    | reserved, 0                                                            |
//
// Section table: section_count entries of {u32 tag, u32 offset, u32 size, u32 count}. A section
// starts on a 4-byte boundary (DATA on 16) and holds `count` fixed-size records, except STRS and DATA
// (raw bytes, count = 0). Readers ignore tags they do not know.
//
// | tag  | record (bytes)                                                                     |
// |------|------------------------------------------------------------------------------------|
// | STRS | string pool; a str is {u32 offset, u32 length} with a NUL at offset+length          |
// | DATA | SPIR-V blobs, each 16-byte aligned                                                 |
// | BLOB | {u32 offset (in file), u32 size (bytes), u64 xxh3 of the bytes} (16)               |
// | SHDR | {str name, u32 stage, u32 blob, str entry_point} (24)                               |
// | BIND | {str name, u32 binding, u32 descriptor_type, u32 count, u32 stage_flags} (24)       |
// | SETL | {list<BIND> bindings} (8); a list is {u32 first, u32 count}                         |
// | IDXS | u32 pool for index lists (4)                                                       |
// | GFXS | graphics state, 99 u32 fields in the order of visit(GraphicsState) below (396)     |
// | PIPE | {str name, u32 kind, list<IDXS> shaders, list<IDXS> set_layouts, u32 push_size,     |
// |      |  u32 push_stages, u32 gfx_state (GFXS index or 0xFFFFFFFF)} (40), sorted by name    |
#include "statepack/archive_format.hpp"

#define XXH_STATIC_LINKING_ONLY  // XXH3_state_t on the stack
#include <xxhash.h>

#include <algorithm>
#include <bit>
#include <cstring>
#include <map>
#include <optional>

static_assert(std::endian::native == std::endian::little,
              "SPIR-V blobs are handed to Vulkan in place; big-endian hosts need a byte-swapping path");

namespace statepack::format {
namespace {

constexpr uint32_t make_tag(const char (&s)[5]) {
  return uint32_t(uint8_t(s[0])) | uint32_t(uint8_t(s[1])) << 8 | uint32_t(uint8_t(s[2])) << 16 |
         uint32_t(uint8_t(s[3])) << 24;
}
constexpr uint32_t kTagStrings = make_tag("STRS"), kTagData = make_tag("DATA"), kTagBlobs = make_tag("BLOB"),
                   kTagShaders = make_tag("SHDR"), kTagBindings = make_tag("BIND"),
                   kTagSetLayouts = make_tag("SETL"), kTagIndices = make_tag("IDXS"),
                   kTagGraphics = make_tag("GFXS"), kTagPipelines = make_tag("PIPE");
constexpr uint32_t kSpirvMagic = 0x07230203u;
constexpr size_t kChecksumOffset = 40;

// --- field order of every record, shared by the size counter, the writer and the reader ----------
// A visitor V provides u32(uint32_t&), f32(float&), str(std::string&), indices(std::vector<uint32_t>&),
// bindings(std::vector<Binding>&), and graphics(Pipeline&).

template <class V>
void visit(V& v, Shader& s) {
  v.str(s.name), v.u32(s.stage), v.u32(s.blob), v.str(s.entry_point);
}
template <class V>
void visit(V& v, Binding& b) {
  v.str(b.name), v.u32(b.binding), v.u32(b.descriptor_type), v.u32(b.count), v.u32(b.stage_flags);
}
template <class V>
void visit(V& v, SetLayout& s) {
  v.bindings(s.bindings);
}
template <class V>
void visit(V& v, StencilOpState& s) {
  v.u32(s.fail_op), v.u32(s.pass_op), v.u32(s.depth_fail_op), v.u32(s.compare_op);
}
template <class V>
void visit(V& v, BlendAttachment& b) {
  v.u32(b.enable), v.u32(b.src_color), v.u32(b.dst_color), v.u32(b.color_op);
  v.u32(b.src_alpha), v.u32(b.dst_alpha), v.u32(b.alpha_op), v.u32(b.write_mask);
}
template <class V>
void visit(V& v, GraphicsState& g) {
  v.u32(g.topology), v.u32(g.polygon_mode), v.u32(g.cull_mode), v.u32(g.front_face), v.u32(g.depth_clamp);
  v.f32(g.depth_bias), v.f32(g.depth_bias_clamp), v.f32(g.depth_bias_slope);
  v.u32(g.depth_test), v.u32(g.depth_write), v.u32(g.depth_compare);
  v.u32(g.stencil_test), v.u32(g.stencil_read_mask), v.u32(g.stencil_write_mask);
  visit(v, g.front), visit(v, g.back);
  v.u32(g.samples), v.u32(g.sample_mask), v.u32(g.alpha_to_coverage), v.u32(g.color_count);
  for (auto& f : g.color_formats) v.u32(f);
  v.u32(g.depth_stencil_format);
  for (auto& b : g.blend) visit(v, b);
}
template <class V>
void visit(V& v, Pipeline& p) {
  v.str(p.name);
  auto kind = static_cast<uint32_t>(p.kind);
  v.u32(kind);
  p.kind = static_cast<PipelineKind>(kind);
  v.indices(p.shaders), v.indices(p.set_layouts);
  v.u32(p.push_constant_size), v.u32(p.push_constant_stages);
  v.graphics(p);
}

// Counts a record's encoded size.
struct SizeCounter {
  uint32_t bytes = 0;
  void u32(uint32_t&) { bytes += 4; }
  void f32(float&) { bytes += 4; }
  void str(std::string&) { bytes += 8; }
  void indices(std::vector<uint32_t>&) { bytes += 8; }
  void bindings(std::vector<Binding>&) { bytes += 8; }
  void graphics(Pipeline&) { bytes += 4; }
};
template <class T>
uint32_t record_size() {
  SizeCounter counter;
  T record{};
  visit(counter, record);
  return counter.bytes;
}

// --- writing ---------------------------------------------------------------------------------------

void put_u32(std::vector<uint8_t>& out, uint32_t value) {
  for (int i = 0; i < 4; ++i) out.push_back(uint8_t(value >> (8 * i)));
}
void put_u64(std::vector<uint8_t>& out, uint64_t value) {
  for (int i = 0; i < 8; ++i) out.push_back(uint8_t(value >> (8 * i)));
}
void set_u64(std::vector<uint8_t>& out, size_t at, uint64_t value) {
  for (int i = 0; i < 8; ++i) out[at + i] = uint8_t(value >> (8 * i));
}

struct Writer {
  std::vector<uint8_t> strings;
  std::map<std::string, uint32_t> string_offsets;  // identical strings are stored once
  std::vector<uint8_t> bindings_section, indices_section, graphics_section;
  uint32_t binding_count = 0, index_count = 0, graphics_count = 0;
  std::vector<uint8_t>* out = nullptr;  // the record section being written

  void u32(uint32_t& value) { put_u32(*out, value); }
  void f32(float& value) { put_u32(*out, std::bit_cast<uint32_t>(value)); }
  void str(std::string& s) {
    auto [it, inserted] = string_offsets.try_emplace(s, uint32_t(strings.size()));
    if (inserted) {
      strings.insert(strings.end(), s.begin(), s.end());
      strings.push_back(0);
    }
    put_u32(*out, it->second), put_u32(*out, uint32_t(s.size()));
  }
  void indices(std::vector<uint32_t>& list) {
    put_u32(*out, index_count), put_u32(*out, uint32_t(list.size()));
    for (uint32_t i : list) put_u32(indices_section, i);
    index_count += uint32_t(list.size());
  }
  void bindings(std::vector<Binding>& list) {
    put_u32(*out, binding_count), put_u32(*out, uint32_t(list.size()));
    auto* saved = out;
    out = &bindings_section;
    for (auto& b : list) visit(*this, b);
    out = saved;
    binding_count += uint32_t(list.size());
  }
  void graphics(Pipeline& p) {
    if (p.kind != PipelineKind::graphics) return put_u32(*out, kNone);
    put_u32(*out, graphics_count++);
    auto* saved = out;
    out = &graphics_section;
    visit(*this, p.graphics);
    out = saved;
  }

  template <class T>
  std::vector<uint8_t> records(std::vector<T>& items) {
    std::vector<uint8_t> section;
    out = &section;
    for (auto& item : items) visit(*this, item);
    return section;
  }
};

struct SectionOut {
  uint32_t tag;
  std::vector<uint8_t> bytes;
  uint32_t count;
  uint32_t alignment;
};

// --- reading ---------------------------------------------------------------------------------------

uint32_t get_u32(const uint8_t* p) {
  return uint32_t(p[0]) | uint32_t(p[1]) << 8 | uint32_t(p[2]) << 16 | uint32_t(p[3]) << 24;
}
uint64_t get_u64(const uint8_t* p) {
  return uint64_t(get_u32(p)) | uint64_t(get_u32(p + 4)) << 32;
}

struct Section {
  uint32_t offset = 0, size = 0, count = 0;
  bool present = false;
};

Error corrupt(std::string message) {
  return Error{ErrorCode::corrupt, "corrupt archive: " + std::move(message)};
}

// Reads records from one section; remembers the first problem instead of throwing.
struct Reader {
  std::span<const uint8_t> file;
  Section strings, bindings_section, indices_section, graphics_section;
  const uint8_t* cursor = nullptr;
  std::optional<std::string> problem;
  std::vector<GraphicsState> graphics_states;  // decoded lazily per pipeline

  void fail(std::string message) {
    if (!problem) problem = std::move(message);
  }
  uint32_t next() {
    uint32_t value = get_u32(cursor);
    cursor += 4;
    return value;
  }
  void u32(uint32_t& value) { value = next(); }
  void f32(float& value) { value = std::bit_cast<float>(next()); }
  void str(std::string& s) {
    uint32_t offset = next(), length = next();
    if (uint64_t(offset) + length >= strings.size) return fail("string reference outside the string pool");
    const uint8_t* p = file.data() + strings.offset + offset;
    if (p[length] != 0) return fail("string is not NUL-terminated");
    s.assign(reinterpret_cast<const char*>(p), length);
  }
  // Checks a {first, count} list against a section of `count` records; returns the first record.
  std::optional<uint32_t> list(const Section& target, uint32_t& count, const char* what) {
    uint32_t first = next();
    count = next();
    if (uint64_t(first) + count > target.count) {
      fail(std::string(what) + " list outside its section");
      return std::nullopt;
    }
    return first;
  }
  void indices(std::vector<uint32_t>& out) {
    uint32_t count = 0;
    auto first = list(indices_section, count, "index");
    if (!first) return;
    out.resize(count);
    const uint8_t* p = file.data() + indices_section.offset + size_t(*first) * 4;
    for (uint32_t i = 0; i < count; ++i) out[i] = get_u32(p + 4 * i);
  }
  void bindings(std::vector<Binding>& out) {
    uint32_t count = 0;
    auto first = list(bindings_section, count, "binding");
    if (!first) return;
    out.resize(count);
    const uint8_t* saved = cursor;
    cursor = file.data() + bindings_section.offset + size_t(*first) * record_size<Binding>();
    for (auto& b : out) visit(*this, b);
    cursor = saved;
  }
  void graphics(Pipeline& p) {
    uint32_t index = next();
    if (p.kind != PipelineKind::graphics) {
      if (index != kNone) fail("compute pipeline '" + p.name + "' has a graphics state");
      return;
    }
    if (index >= graphics_section.count)
      return fail("pipeline '" + p.name + "' graphics state index out of range");
    const uint8_t* saved = cursor;
    cursor = file.data() + graphics_section.offset + size_t(index) * record_size<GraphicsState>();
    visit(*this, p.graphics);
    cursor = saved;
  }
  template <class T>
  std::vector<T> records(const Section& section) {
    std::vector<T> items(section.count);
    cursor = file.data() + section.offset;
    for (auto& item : items) visit(*this, item);
    return items;
  }
};

bool is_single_stage(uint32_t stage) {
  constexpr uint32_t kKnownStages = 0x3F;  // VERTEX..COMPUTE
  return std::has_single_bit(stage) && (stage & kKnownStages) != 0;
}

Result<void> validate(const Contents& c) {
  constexpr uint32_t kComputeStage = 0x20, kVertexStage = 0x1;
  for (size_t i = 0; i < c.shaders.size(); ++i) {
    const Shader& s = c.shaders[i];
    if (!is_single_stage(s.stage)) return corrupt("shader '" + s.name + "' has an invalid stage");
    if (s.blob >= c.spirv.size()) return corrupt("shader '" + s.name + "' refers to a missing SPIR-V blob");
    if (s.entry_point.empty()) return corrupt("shader '" + s.name + "' has no entry point");
  }
  for (const SetLayout& layout : c.set_layouts) {
    for (size_t i = 0; i < layout.bindings.size(); ++i) {
      const Binding& b = layout.bindings[i];
      if (b.descriptor_type > 10) return corrupt("binding '" + b.name + "' has an unknown descriptor type");
      if (i > 0 && layout.bindings[i - 1].binding >= b.binding)
        return corrupt("binding '" + b.name + "' is out of order or duplicated");
    }
  }
  for (size_t i = 0; i < c.pipelines.size(); ++i) {
    const Pipeline& p = c.pipelines[i];
    if (i > 0 && c.pipelines[i - 1].name >= p.name)
      return corrupt("pipeline '" + p.name + "' breaks the sorted, unique name index");
    if (p.kind != PipelineKind::graphics && p.kind != PipelineKind::compute)
      return corrupt("pipeline '" + p.name + "' has an unknown kind");
    uint32_t stages = 0;
    for (uint32_t s : p.shaders) {
      if (s >= c.shaders.size()) return corrupt("pipeline '" + p.name + "' refers to a missing shader");
      if (stages & c.shaders[s].stage)
        return corrupt("pipeline '" + p.name + "' has two shaders for one stage");
      stages |= c.shaders[s].stage;
    }
    if (p.kind == PipelineKind::compute && stages != kComputeStage)
      return corrupt("compute pipeline '" + p.name + "' needs exactly one compute shader");
    if (p.kind == PipelineKind::graphics && (!(stages & kVertexStage) || (stages & kComputeStage)))
      return corrupt("graphics pipeline '" + p.name + "' needs a vertex shader and no compute shader");
    for (uint32_t l : p.set_layouts)
      if (l != kNone && l >= c.set_layouts.size())
        return corrupt("pipeline '" + p.name + "' refers to a missing set layout");
    if (p.graphics.color_count > kMaxColorTargets)
      return corrupt("pipeline '" + p.name + "' has more than 8 render targets");
  }
  return {};
}

}  // namespace

uint64_t hash_bytes(std::span<const uint8_t> bytes) {
  return XXH3_64bits(bytes.data(), bytes.size());
}

static uint64_t archive_checksum(std::span<const uint8_t> file) {
  XXH3_state_t state;
  XXH3_64bits_reset(&state);
  XXH3_64bits_update(&state, file.data(), kChecksumOffset);
  const uint8_t zeros[8] = {};
  XXH3_64bits_update(&state, zeros, sizeof zeros);
  XXH3_64bits_update(&state, file.data() + kChecksumOffset + 8, file.size() - kChecksumOffset - 8);
  return XXH3_64bits_digest(&state);
}

std::vector<uint8_t> encode(const Contents& input) {
  Contents c = input;  // the visitors take mutable references
  std::sort(c.pipelines.begin(), c.pipelines.end(),
            [](const Pipeline& a, const Pipeline& b) { return a.name < b.name; });

  Writer w;
  std::vector<uint8_t> shaders = w.records(c.shaders);
  std::vector<uint8_t> set_layouts = w.records(c.set_layouts);
  std::vector<uint8_t> pipelines = w.records(c.pipelines);

  std::vector<SectionOut> sections;
  sections.push_back({kTagStrings, std::move(w.strings), 0, 4});
  sections.push_back({kTagBlobs, {}, uint32_t(c.spirv.size()), 4});  // filled once DATA is placed
  sections.push_back({kTagShaders, std::move(shaders), uint32_t(c.shaders.size()), 4});
  sections.push_back({kTagBindings, std::move(w.bindings_section), w.binding_count, 4});
  sections.push_back({kTagSetLayouts, std::move(set_layouts), uint32_t(c.set_layouts.size()), 4});
  sections.push_back({kTagIndices, std::move(w.indices_section), w.index_count, 4});
  sections.push_back({kTagGraphics, std::move(w.graphics_section), w.graphics_count, 4});
  sections.push_back({kTagPipelines, std::move(pipelines), uint32_t(c.pipelines.size()), 4});
  sections.push_back({kTagData, {}, 0, kBlobAlignment});

  // Lay out: header, section table, sections in order. BLOB's size is known before DATA's offsets.
  sections[1].bytes.resize(c.spirv.size() * 16);
  std::vector<uint32_t> offsets(sections.size());
  size_t cursor = kHeaderSize + sections.size() * 16;
  auto align = [](size_t v, size_t a) { return (v + a - 1) / a * a; };
  for (size_t i = 0; i + 1 < sections.size(); ++i) {
    cursor = align(cursor, sections[i].alignment);
    offsets[i] = uint32_t(cursor);
    cursor += sections[i].bytes.size();
  }
  // DATA: blobs, each 16-byte aligned in the file.
  size_t data_start = align(cursor, kBlobAlignment);
  std::vector<uint8_t>& data = sections.back().bytes;
  std::vector<uint8_t> blob_table;
  for (auto blob : c.spirv) {
    data.resize(align(data.size(), kBlobAlignment));
    auto bytes = std::as_bytes(blob);
    put_u32(blob_table, uint32_t(data_start + data.size()));
    put_u32(blob_table, uint32_t(bytes.size()));
    put_u64(blob_table, hash_bytes({reinterpret_cast<const uint8_t*>(bytes.data()), bytes.size()}));
    const auto* first = reinterpret_cast<const uint8_t*>(bytes.data());
    data.insert(data.end(), first, first + bytes.size());
  }
  sections[1].bytes = std::move(blob_table);
  offsets.back() = uint32_t(data_start);

  std::vector<uint8_t> out;
  out.insert(out.end(), kMagic.begin(), kMagic.end());
  put_u32(out, kFormatVersion);
  put_u32(out, kOldestReadableVersion);
  put_u32(out, kHeaderSize);
  put_u32(out, c.producer_version);
  put_u32(out, c.content_version);
  put_u32(out, c.backends);
  put_u64(out, 0);  // file_size, patched below
  put_u64(out, 0);  // checksum, patched below
  put_u32(out, uint32_t(sections.size()));
  put_u32(out, kHeaderSize);
  put_u64(out, 0);
  for (size_t i = 0; i < sections.size(); ++i) {
    put_u32(out, sections[i].tag);
    put_u32(out, offsets[i]);
    put_u32(out, uint32_t(sections[i].bytes.size()));
    put_u32(out, sections[i].count);
  }
  for (size_t i = 0; i < sections.size(); ++i) {
    out.resize(offsets[i], 0);
    out.insert(out.end(), sections[i].bytes.begin(), sections[i].bytes.end());
  }
  set_u64(out, 32, out.size());
  set_u64(out, kChecksumOffset, archive_checksum(out));
  return out;
}

Result<Contents> decode(std::span<const uint8_t> file) {
  if (reinterpret_cast<uintptr_t>(file.data()) % 4 != 0)
    return Error{ErrorCode::misaligned_memory,
                 "archive memory must be 4-byte aligned to hand SPIR-V to Vulkan"};
  if (file.size() < kHeaderSize) {
    if (file.size() >= kMagic.size() && !std::equal(kMagic.begin(), kMagic.end(), file.begin()))
      return Error{ErrorCode::bad_magic, "not a statepack archive (wrong magic bytes)"};
    return Error{ErrorCode::truncated, "truncated archive: " + std::to_string(file.size()) +
                                           " bytes is shorter than the 64-byte header"};
  }
  if (!std::equal(kMagic.begin(), kMagic.end(), file.begin()))
    return Error{ErrorCode::bad_magic, "not a statepack archive (wrong magic bytes)"};
  const uint8_t* h = file.data();
  uint32_t version = get_u32(h + 8), oldest = get_u32(h + 12), header_size = get_u32(h + 16);
  if (oldest > kFormatVersion)
    return Error{ErrorCode::unsupported_version, "archive format version " + std::to_string(version) +
                                                     " needs a reader of version " + std::to_string(oldest) +
                                                     " or newer; this reader understands version " +
                                                     std::to_string(kFormatVersion)};
  uint64_t file_size = get_u64(h + 32);
  if (file_size > file.size())
    return Error{ErrorCode::truncated, "truncated archive: header says " + std::to_string(file_size) +
                                           " bytes, got " + std::to_string(file.size())};
  if (file_size < file.size())
    return corrupt("header says " + std::to_string(file_size) + " bytes but " + std::to_string(file.size()) +
                   " were given (trailing data)");
  if (archive_checksum(file) != get_u64(h + kChecksumOffset))
    return Error{ErrorCode::checksum_mismatch, "archive checksum mismatch: the file is damaged"};
  if (header_size < kHeaderSize || header_size > file.size()) return corrupt("bad header size");

  Contents c;
  c.format_version = version;
  c.producer_version = get_u32(h + 20);
  c.content_version = get_u32(h + 24);
  c.backends = get_u32(h + 28);
  uint32_t section_count = get_u32(h + 48), table = get_u32(h + 52);
  if (table < header_size || table % 4 != 0 || uint64_t(table) + uint64_t(section_count) * 16 > file.size())
    return corrupt("section table outside the file");

  std::map<uint32_t, Section> sections;
  for (uint32_t i = 0; i < section_count; ++i) {
    const uint8_t* e = file.data() + table + 16 * i;
    Section s{get_u32(e + 4), get_u32(e + 8), get_u32(e + 12), true};
    if (s.offset % 4 != 0 || uint64_t(s.offset) + s.size > file.size())
      return corrupt("section " + std::to_string(i) + " lies outside the file");
    if (!sections.emplace(get_u32(e), s).second)
      return corrupt("section " + std::to_string(i) + " is repeated");
  }
  auto need = [&](uint32_t tag, const char* name, uint32_t record) -> Result<Section> {
    auto it = sections.find(tag);
    if (it == sections.end()) return corrupt(std::string("missing section ") + name);
    if (record != 0 && uint64_t(it->second.count) * record != it->second.size)
      return corrupt(std::string("section ") + name + " size does not match its record count");
    return it->second;
  };
  auto strings = need(kTagStrings, "STRS", 0), data = need(kTagData, "DATA", 0),
       blobs = need(kTagBlobs, "BLOB", 16), shaders = need(kTagShaders, "SHDR", record_size<Shader>()),
       bindings = need(kTagBindings, "BIND", record_size<Binding>()),
       set_layouts = need(kTagSetLayouts, "SETL", record_size<SetLayout>()),
       indices = need(kTagIndices, "IDXS", 4),
       graphics = need(kTagGraphics, "GFXS", record_size<GraphicsState>()),
       pipelines = need(kTagPipelines, "PIPE", record_size<Pipeline>());
  for (auto* r :
       {&strings, &data, &blobs, &shaders, &bindings, &set_layouts, &indices, &graphics, &pipelines})
    if (!*r) return r->error();

  // Blobs: inside DATA, aligned, a whole number of SPIR-V words, content hash matching.
  for (uint32_t i = 0; i < blobs->count; ++i) {
    const uint8_t* e = file.data() + blobs->offset + 16 * i;
    uint32_t offset = get_u32(e), size = get_u32(e + 4);
    if (offset % kBlobAlignment != 0 || size == 0 || size % 4 != 0 || offset < data->offset ||
        uint64_t(offset) + size > uint64_t(data->offset) + data->size)
      return corrupt("SPIR-V blob " + std::to_string(i) + " has a bad offset or size");
    std::span<const uint8_t> bytes = file.subspan(offset, size);
    if (hash_bytes(bytes) != get_u64(e + 8))
      return Error{ErrorCode::checksum_mismatch,
                   "SPIR-V blob " + std::to_string(i) + " content hash mismatch"};
    if (get_u32(bytes.data()) != kSpirvMagic) return corrupt("blob " + std::to_string(i) + " is not SPIR-V");
    c.spirv.emplace_back(reinterpret_cast<const uint32_t*>(bytes.data()), size / 4);
  }

  Reader r{file, *strings, *bindings, *indices, *graphics};
  c.shaders = r.records<Shader>(*shaders);
  c.set_layouts = r.records<SetLayout>(*set_layouts);
  c.pipelines = r.records<Pipeline>(*pipelines);
  if (r.problem) return corrupt(*r.problem);
  if (auto valid = validate(c); !valid) return valid.error();
  return c;
}

}  // namespace statepack::format
