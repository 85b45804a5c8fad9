// statepack archive format (versions 1 to 3): encoder and validating decoder.
//
// All integers are little-endian; strings are UTF-8. docs/archive-format.md is the full spec; the
// tables below are its summary, kept next to the code that reads them.
//
// Header (64 bytes at offset 0)
// | off | type   | field                                                                  |
// |-----|--------|------------------------------------------------------------------------|
// |   0 | u8[8]  | magic 89 'S' 'P' 'K' 0D 0A 1A 0A                                       |
// |   8 | u32    | format_version (3)                                                     |
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
// A str is {u32 offset, u32 length} into STRS with a NUL at offset+length; a list<X> is
// {u32 first, u32 count} into section X. Record layouts are the visit() functions below, in order.
//
// | tag  | record                                                                           |
// |------|----------------------------------------------------------------------------------|
// | STRS | string pool                                                                      |
// | DATA | SPIR-V blobs, each 16-byte aligned                                               |
// | BLOB | u32 offset (in file), u32 size (bytes), u64 xxh3 of the bytes                     |
// | IDXS | u32 pool for index lists                                                         |
// | SHDR | shader: str name, u32 stage, u32 blob, str entry_point                            |
// | SIDX | u32 shader index of each standalone shader, sorted by shader name                |
// | SAMP | sampler: 15 u32/f32 fields                                                        |
// | BIND | binding: str name, binding, descriptor_type, count, stage_flags, immutable_sampler |
// | SETL | set layout: str name, u32 binding_index, list<BIND>                               |
// | ATCH | attachment: format, samples, load/store ops, stencil ops, layouts                  |
// | AREF | attachment reference: attachment, layout                                         |
// | SUBP | subpass: list<AREF> inputs, colors, resolves; AREF depth; list<IDXS> preserve      |
// | DEPS | dependency: subpasses, stages, access masks, flags                                |
// | RPAS | render pass: str name, list<ATCH>, list<SUBP>, list<DEPS>                          |
// | VTXB | vertex binding: binding, stride, input_rate                                       |
// | VTXA | vertex attribute: location, binding, format, offset                               |
// | GFXS | graphics state (see visit(GraphicsState)), then the pipeline's render pass, subpass |
// | PIPE | pipeline: str name, kind, list<IDXS> shaders, list<IDXS> set layouts, push size,   |
// |      | push stages, u32 GFXS index (0xFFFFFFFF for compute); sorted by name              |
// | PEXT | (format 2) one per PIPE record, same order: u32 dynamic states, list<SPEC>       |
// | SPEC | (format 2) specialization constant: str name, stage, constant id, size, u64 value |
// | TESS | (format 3) one per PIPE record, same order, present only when a pipeline          |
// |      | tessellates: u32 patch control points (0 unless the topology is PATCH_LIST)       |
// | GLPI | (OpenGL block) GL pipeline: str name, kind, list<GLSH>, list<GLBD>, u32 GFXS index |
// |      | (0xFFFFFFFF for compute; its render pass must be none), list<SPEC>; sorted by name |
// | GLSH | GL shader: str name, u32 stage, u32 blob, str entry_point                        |
// | GLBD | GL binding: str name, u32 namespace (0 UBO, 1 SSBO, 2 texture, 3 image), binding, |
// |      | count, stages                                                                    |
// The OpenGL block's three sections are written only when the archive holds GL pipelines; readers that
// do not know them ignore them (so they change no version number).
#include "archive_format.hpp"

#include "support/failure.hpp"

#define XXH_STATIC_LINKING_ONLY  // XXH3_state_t on the stack
#include <xxhash.h>

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstring>
#include <map>
#include <optional>
#include <set>
#include <string_view>

static_assert(std::endian::native == std::endian::little,
              "SPIR-V blobs are handed to Vulkan in place; big-endian hosts need a byte-swapping path");

namespace statepack::format {
namespace {

constexpr uint32_t make_tag(const char (&s)[5]) {
  return uint32_t(uint8_t(s[0])) | uint32_t(uint8_t(s[1])) << 8 | uint32_t(uint8_t(s[2])) << 16 |
         uint32_t(uint8_t(s[3])) << 24;
}
constexpr uint32_t kTagStrings = make_tag("STRS"), kTagData = make_tag("DATA"), kTagBlobs = make_tag("BLOB"),
                   kTagIndices = make_tag("IDXS"), kTagStandalone = make_tag("SIDX"),
                   kTagGraphics = make_tag("GFXS");
constexpr uint32_t kSpirvMagic = 0x07230203u;
constexpr uint32_t kTopologyPatchList =
    10;  // VK_PRIMITIVE_TOPOLOGY_PATCH_LIST (the codec has no Vulkan headers)
constexpr size_t kChecksumOffset = 40;
// The decoding budget: encoded bytes that records may materialise, lists and strings included.
constexpr uint64_t kExpansionFactor = 8, kExpansionSlack = 1 << 20;
#ifdef FUZZING_BUILD_MODE_UNSAFE_FOR_PRODUCTION
constexpr bool kFuzzing = true;
#else
constexpr bool kFuzzing = false;
#endif

// The GFXS record: a graphics pipeline's fixed-function state, then its render pass and subpass. Those
// two belong to the pipeline (format::Pipeline holds them); format 1 put them here, and here they stay.
struct GraphicsRecord {
  GraphicsState state;
  uint32_t render_pass = kNone;
  uint32_t subpass = 0;
};

// The section each record type lives in.
template <class T>
struct Tag;
// clang-format off
template <> struct Tag<Shader> { static constexpr uint32_t value = make_tag("SHDR"); };
template <> struct Tag<Sampler> { static constexpr uint32_t value = make_tag("SAMP"); };
template <> struct Tag<Binding> { static constexpr uint32_t value = make_tag("BIND"); };
template <> struct Tag<SetLayout> { static constexpr uint32_t value = make_tag("SETL"); };
template <> struct Tag<Attachment> { static constexpr uint32_t value = make_tag("ATCH"); };
template <> struct Tag<AttachmentRef> { static constexpr uint32_t value = make_tag("AREF"); };
template <> struct Tag<Subpass> { static constexpr uint32_t value = make_tag("SUBP"); };
template <> struct Tag<Dependency> { static constexpr uint32_t value = make_tag("DEPS"); };
template <> struct Tag<RenderPass> { static constexpr uint32_t value = make_tag("RPAS"); };
template <> struct Tag<VertexBinding> { static constexpr uint32_t value = make_tag("VTXB"); };
template <> struct Tag<VertexAttribute> { static constexpr uint32_t value = make_tag("VTXA"); };
template <> struct Tag<GraphicsRecord> { static constexpr uint32_t value = make_tag("GFXS"); };
template <> struct Tag<Pipeline> { static constexpr uint32_t value = make_tag("PIPE"); };
template <> struct Tag<SpecConstant> { static constexpr uint32_t value = make_tag("SPEC"); };
template <> struct Tag<GlPipeline> { static constexpr uint32_t value = make_tag("GLPI"); };
template <> struct Tag<GlShader> { static constexpr uint32_t value = make_tag("GLSH"); };
template <> struct Tag<GlBinding> { static constexpr uint32_t value = make_tag("GLBD"); };
// clang-format on

// --- field order of every record, shared by the size counter, the writer and the reader ----------
// A visitor V provides u32(uint32_t&), f32(float&), str(std::string&), indices(std::vector<uint32_t>&),
// list(std::vector<T>&) and graphics(Pipeline&).

template <class V>
void visit(V& v, Shader& s) {
  v.str(s.name), v.u32(s.stage), v.u32(s.blob), v.str(s.entry_point);
}
template <class V>
void visit(V& v, Sampler& s) {
  v.u32(s.mag_filter), v.u32(s.min_filter), v.u32(s.mipmap_mode);
  v.u32(s.address_u), v.u32(s.address_v), v.u32(s.address_w);
  v.f32(s.mip_lod_bias), v.u32(s.anisotropy_enable), v.f32(s.max_anisotropy);
  v.u32(s.compare_enable), v.u32(s.compare_op), v.f32(s.min_lod), v.f32(s.max_lod);
  v.u32(s.border_color), v.u32(s.unnormalized_coordinates);
}
template <class V>
void visit(V& v, Binding& b) {
  v.str(b.name), v.u32(b.binding), v.u32(b.descriptor_type), v.u32(b.count), v.u32(b.stage_flags);
  v.u32(b.immutable_sampler);
}
template <class V>
void visit(V& v, SetLayout& s) {
  v.str(s.name), v.u32(s.binding_index), v.list(s.bindings);
}
template <class V>
void visit(V& v, Attachment& a) {
  v.u32(a.format), v.u32(a.samples), v.u32(a.load_op), v.u32(a.store_op);
  v.u32(a.stencil_load_op), v.u32(a.stencil_store_op), v.u32(a.initial_layout), v.u32(a.final_layout);
}
template <class V>
void visit(V& v, AttachmentRef& r) {
  v.u32(r.attachment), v.u32(r.layout);
}
template <class V>
void visit(V& v, Subpass& s) {
  v.list(s.inputs), v.list(s.colors), v.list(s.resolves);
  visit(v, s.depth_stencil);
  v.indices(s.preserve);
}
template <class V>
void visit(V& v, Dependency& d) {
  v.u32(d.src_subpass), v.u32(d.dst_subpass), v.u32(d.src_stages), v.u32(d.dst_stages);
  v.u32(d.src_access), v.u32(d.dst_access), v.u32(d.flags);
}
template <class V>
void visit(V& v, RenderPass& r) {
  v.str(r.name), v.list(r.attachments), v.list(r.subpasses), v.list(r.dependencies);
}
template <class V>
void visit(V& v, VertexBinding& b) {
  v.u32(b.binding), v.u32(b.stride), v.u32(b.input_rate);
}
template <class V>
void visit(V& v, VertexAttribute& a) {
  v.u32(a.location), v.u32(a.binding), v.u32(a.format), v.u32(a.offset);
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
  v.list(g.vertex_bindings), v.list(g.vertex_attributes);
}
template <class V>
void visit(V& v, GraphicsRecord& r) {
  visit(v, r.state);
  v.u32(r.render_pass), v.u32(r.subpass);
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

// The PEXT record: what format 2 added to a pipeline, kept out of PIPE so PIPE records keep their size.
struct PipelineExtras {
  uint32_t dynamic_states = kDynamicLegacy;
  std::vector<SpecConstant> constants;
};
template <>
struct Tag<PipelineExtras> {
  static constexpr uint32_t value = make_tag("PEXT");
};

template <class V>
void visit(V& v, SpecConstant& s) {
  uint32_t low = uint32_t(s.value), high = uint32_t(s.value >> 32);
  v.str(s.name), v.u32(s.stage), v.u32(s.constant_id), v.u32(s.size), v.u32(low), v.u32(high);
  s.value = uint64_t(low) | uint64_t(high) << 32;
}

// The OpenGL block's records.
template <class V>
void visit(V& v, GlShader& s) {
  v.str(s.name), v.u32(s.stage), v.u32(s.blob), v.str(s.entry_point);
}
template <class V>
void visit(V& v, GlBinding& b) {
  v.str(b.name), v.u32(b.kind), v.u32(b.binding), v.u32(b.count), v.u32(b.stages);
}
template <class V>
void visit(V& v, GlPipeline& p) {
  v.str(p.name);
  auto kind = static_cast<uint32_t>(p.kind);
  v.u32(kind);
  p.kind = static_cast<PipelineKind>(kind);
  v.list(p.shaders), v.list(p.bindings);
  v.graphics(p);
  v.list(p.constants);
}
template <class V>
void visit(V& v, PipelineExtras& e) {
  v.u32(e.dynamic_states), v.list(e.constants);
}

// A pipeline's patch control points, one record per pipeline of its list, in a section written only
// when one of them tessellates: TESS (format 3) for the Vulkan pipelines, GLTS (format 4) for OpenGL's.
template <uint32_t kTag>
struct PatchControlPoints {
  uint32_t patch_control_points = 0;
};
template <uint32_t kTag>
struct Tag<PatchControlPoints<kTag>> {
  static constexpr uint32_t value = kTag;
};
template <class V, uint32_t kTag>
void visit(V& v, PatchControlPoints<kTag>& t) {
  v.u32(t.patch_control_points);
}
using PipelineTessellation = PatchControlPoints<make_tag("TESS")>;
using GlPipelineTessellation = PatchControlPoints<make_tag("GLTS")>;

// Appends one Record per pipeline when any of `pipelines` tessellates; returns whether one does.
template <class Record, class Out, class Pipelines>
bool append_patch_control_points(Out& w, const Pipelines& pipelines) {
  const bool any = std::any_of(pipelines.begin(), pipelines.end(), [](const auto& p) {
    return p.kind == PipelineKind::graphics && p.graphics.patch_control_points != 0;
  });
  if (any)
    for (const auto& p : pipelines) {
      Record t{p.kind == PipelineKind::graphics ? p.graphics.patch_control_points : 0};
      w.append(t);
    }
  return any;
}

// Writes a record and everything its lists hold inline, lengths first: equal records give equal bytes,
// so the bytes are a key for deduplication (record_key).
struct KeyWriter {
  std::string out;
  void u32(uint32_t& value) { out.append(reinterpret_cast<const char*>(&value), 4); }
  void f32(float& value) {
    uint32_t bits = std::bit_cast<uint32_t>(value);
    u32(bits);
  }
  void str(std::string& s) {
    uint32_t size = uint32_t(s.size());
    u32(size);
    out += s;
  }
  void indices(std::vector<uint32_t>& list) {
    uint32_t size = uint32_t(list.size());
    u32(size);
    for (uint32_t& i : list) u32(i);
  }
  template <class T>
  void list(std::vector<T>& items) {
    uint32_t size = uint32_t(items.size());
    u32(size);
    for (T& item : items) visit(*this, item);
  }
  template <class P>
  void graphics(P&) {}  // not used for pipelines
};

// Counts a record's encoded size.
struct SizeCounter {
  uint32_t bytes = 0;
  void u32(uint32_t&) { bytes += 4; }
  void f32(float&) { bytes += 4; }
  void str(std::string&) { bytes += 8; }
  void indices(std::vector<uint32_t>&) { bytes += 8; }
  template <class T>
  void list(std::vector<T>&) {
    bytes += 8;
  }
  template <class P>
  void graphics(P&) {
    bytes += 4;
  }
};
template <class T>
uint32_t record_size() {
  static const uint32_t size = [] {  // fixed by the layout: counted once
    SizeCounter counter;
    T record{};
    visit(counter, record);
    return counter.bytes;
  }();
  return size;
}

// Every record section, in file order (the pools a list points into included).
template <class F>
void for_each_record_type(F&& f) {
  f(Shader{}), f(Sampler{}), f(Binding{}), f(SetLayout{}), f(Attachment{}), f(AttachmentRef{});
  f(Subpass{}), f(Dependency{}), f(RenderPass{}), f(VertexBinding{}), f(VertexAttribute{});
  f(GraphicsRecord{}), f(Pipeline{});
}
// The OpenGL block's sections, written only when there are GL pipelines.
template <class F>
void for_each_gl_record_type(F&& f) {
  f(GlShader{}), f(GlBinding{}), f(GlPipeline{});
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

struct PoolOut {
  std::vector<uint8_t> bytes;
  uint32_t count = 0;
};

struct Writer {
  std::vector<uint8_t> strings;
  std::map<std::string, uint32_t> string_offsets;  // identical strings are stored once
  std::map<uint32_t, PoolOut> pools;               // by tag
  std::vector<uint8_t>* out = nullptr;             // the record being written

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
    PoolOut& pool = pools[kTagIndices];
    put_u32(*out, pool.count), put_u32(*out, uint32_t(list.size()));
    for (uint32_t i : list) put_u32(pool.bytes, i);
    pool.count += uint32_t(list.size());
  }
  template <class T>
  uint32_t append(T& item) {  // writes one record into T's section, returns its index
    PoolOut& pool = pools[Tag<T>::value];
    auto* saved = out;
    std::vector<uint8_t> record;
    out = &record;
    visit(*this, item);  // nested lists go to other pools, so this record stays contiguous
    out = saved;
    pool.bytes.insert(pool.bytes.end(), record.begin(), record.end());
    return pool.count++;
  }
  template <class T>
  void list(std::vector<T>& items) {
    // Elements of one list must be contiguous: reserve the range before nested records are added.
    PoolOut& pool = pools[Tag<T>::value];
    uint32_t first = pool.count;
    std::vector<std::vector<uint8_t>> records(items.size());
    pool.count += uint32_t(items.size());
    auto* saved = out;
    for (size_t i = 0; i < items.size(); ++i) {
      out = &records[i];
      visit(*this, items[i]);
    }
    out = saved;
    PoolOut& same_pool = pools[Tag<T>::value];  // map references stay valid across insertions
    for (auto& r : records) same_pool.bytes.insert(same_pool.bytes.end(), r.begin(), r.end());
    put_u32(*out, first), put_u32(*out, uint32_t(items.size()));
  }
  void graphics(Pipeline& p) {
    if (p.kind != PipelineKind::graphics) return put_u32(*out, kNone);
    GraphicsRecord record{p.graphics, p.render_pass, p.subpass};
    put_u32(*out, append(record));
  }
  void graphics(GlPipeline& p) {
    if (p.kind != PipelineKind::graphics) return put_u32(*out, kNone);
    GraphicsRecord record{p.graphics, kNone, 0};
    put_u32(*out, append(record));
  }
};

// --- reading ---------------------------------------------------------------------------------------

// Read for every field of every record: inlined even where the runtime is compiled for size.
[[gnu::always_inline]] inline uint32_t get_u32(const uint8_t* p) {
  return uint32_t(p[0]) | uint32_t(p[1]) << 8 | uint32_t(p[2]) << 16 | uint32_t(p[3]) << 24;
}
uint64_t get_u64(const uint8_t* p) {
  return uint64_t(get_u32(p)) | uint64_t(get_u32(p + 4)) << 32;
}

struct Section {
  uint32_t offset = 0, size = 0, count = 0;
};

using detail::corrupt;

// Reads records; remembers the first problem instead of throwing. Section sizes were checked
// against their record counts before any record is read, and every list against its section.
//
// Lists and strings are references, so records may share them: a few kilobytes of PIPE records that
// all point at one long list would decode into gigabytes. Every element and string byte materialised
// is charged, in encoded bytes, to a budget proportional to the file size (a packager never shares,
// so a real archive decodes to about its own size) before anything is allocated for it.
struct Reader {
  std::span<const uint8_t> file;
  std::map<uint32_t, Section> sections;
  const uint8_t* cursor = nullptr;
  std::optional<std::string> problem;
  uint64_t budget = 0;  // encoded bytes still allowed to be materialised
  uint64_t initial_budget = 0;
  // The top-level record being read, for messages (built only when one is needed): its kind, its index
  // (none while the whole list is charged) and its name once read.
  const char* current_kind = nullptr;
  std::optional<uint32_t> current_index;
  const std::string* current_name = nullptr;

  [[gnu::cold]] void fail(std::string message) {
    if (!problem) problem = std::move(message);
  }
  bool charge(uint64_t bytes) {
    if (bytes <= budget) {
      budget -= bytes;
      return true;
    }
    over_budget();
    return false;
  }
  [[gnu::cold]] void over_budget() {
    fail((!current_kind   ? std::string("the archive")
          : current_index ? current_kind + (" " + std::to_string(*current_index))
                          : current_kind + std::string(" records")) +
         (current_name && !current_name->empty() ? " '" + *current_name + "'" : "") +
         " expands beyond the decoding budget of " + std::to_string(initial_budget) + " bytes (" +
         std::to_string(kExpansionFactor) + " x the file size + " + std::to_string(kExpansionSlack) +
         "): records share lists or strings to amplify the archive");
  }
  // The fields' readers: called for every field of every record, so inlined even at -Os.
  [[gnu::always_inline]] uint32_t next() {
    uint32_t value = get_u32(cursor);
    cursor += 4;
    return value;
  }
  [[gnu::always_inline]] void u32(uint32_t& value) { value = next(); }
  [[gnu::always_inline]] void f32(float& value) { value = std::bit_cast<float>(next()); }
  // A section by tag, through a small direct-mapped memo in front of the map: every string, list and
  // record read looks one up, a few tags over and over. (A tag absent reads as an empty section; the
  // map's nodes do not move, so the memo's pointers stay good.)
  std::array<std::pair<uint32_t, const Section*>, 16> memo{};
  const Section& section(uint32_t tag) {
    auto& m = memo[(tag ^ (tag >> 8) ^ (tag >> 16) ^ (tag >> 24)) & 15];
    if (!m.second || m.first != tag) m = {tag, &sections[tag]};
    return *m.second;
  }
  // The two sections every record reads from, looked up once.
  const Section* strings_section = nullptr;
  const Section* indices_section = nullptr;
  void str(std::string& s) {
    if (!strings_section) strings_section = &section(kTagStrings);
    const Section& strings = *strings_section;
    uint32_t offset = next(), length = next();
    if (uint64_t(offset) + length >= strings.size) return fail("string reference outside the string pool");
    const uint8_t* p = file.data() + strings.offset + offset;
    if (p[length] != 0) return fail("string is not NUL-terminated");
    if (!charge(length)) return;
    s.assign(reinterpret_cast<const char*>(p), length);
  }
  std::optional<uint32_t> range(uint32_t tag, uint32_t& count, const char* what) {
    return range(section(tag), count, what);
  }
  std::optional<uint32_t> range(const Section& in, uint32_t& count, const char* what) {
    uint32_t first = next();
    count = next();
    if (uint64_t(first) + count > in.count) {
      fail(std::string(what) + " list outside its section");
      return std::nullopt;
    }
    return first;
  }
  void indices(std::vector<uint32_t>& out) {
    if (!indices_section) indices_section = &section(kTagIndices);
    uint32_t count = 0;
    auto first = range(*indices_section, count, "index");
    if (!first || !charge(uint64_t(count) * 4)) return;
    out.resize(count);
    const uint8_t* p = file.data() + indices_section->offset + size_t(*first) * 4;
    for (uint32_t i = 0; i < count; ++i) out[i] = get_u32(p + 4 * i);
  }
  template <class T>
  void read_at(uint32_t index, T& item) {
    const uint8_t* saved = cursor;
    cursor = file.data() + section(Tag<T>::value).offset + size_t(index) * record_size<T>();
    visit(*this, item);
    cursor = saved;
  }
  template <class T>
  void list(std::vector<T>& out) {
    uint32_t count = 0;
    auto first = range(Tag<T>::value, count, "record");
    if (!first || !charge(uint64_t(count) * record_size<T>())) return;
    out.resize(count);
    for (uint32_t i = 0; i < count && !problem; ++i) read_at(*first + i, out[i]);
  }
  // Reads the GFXS record a pipeline refers to into its state (and render pass and subpass), straight
  // from the file: false for none (a compute pipeline's kNone, or a problem noted).
  template <class P>
  bool graphics_record(P& p, const char* kind, uint32_t& render_pass, uint32_t& subpass) {
    uint32_t index = next();
    auto what = [&] { return std::string(kind) + " '" + p.name + "'"; };
    if (p.kind != PipelineKind::graphics) {
      if (index != kNone) fail(what() + " is a compute pipeline with a graphics state");
      return false;
    }
    if (index >= section(kTagGraphics).count) {
      fail(what() + ": graphics state index out of range");
      return false;
    }
    if (!charge(record_size<GraphicsRecord>())) return false;
    const uint8_t* saved = cursor;
    cursor = file.data() + section(kTagGraphics).offset + size_t(index) * record_size<GraphicsRecord>();
    visit(*this, p.graphics);  // a GraphicsRecord's fields, in its order (visit(GraphicsRecord&))
    u32(render_pass), u32(subpass);
    cursor = saved;
    return true;
  }
  void graphics(Pipeline& p) { graphics_record(p, "pipeline", p.render_pass, p.subpass); }
  void graphics(GlPipeline& p) {
    uint32_t render_pass = kNone, subpass = 0;
    if (graphics_record(p, "OpenGL pipeline", render_pass, subpass) && render_pass != kNone)
      fail("OpenGL pipeline '" + p.name + "' has a render pass");
  }
  template <class T>
  std::vector<T> all(const char* kind) {
    // Top-level records are charged too: they are in the file, so they cost at most its size.
    const uint32_t count = section(Tag<T>::value).count;
    current_kind = kind;
    current_index.reset();
    if (!charge(uint64_t(count) * record_size<T>())) return {};
    std::vector<T> items(count);
    for (uint32_t i = 0; i < items.size() && !problem; ++i) {
      current_index = i;
      if constexpr (requires { items[i].name; }) current_name = &items[i].name;
      read_at(i, items[i]);
      current_name = nullptr;
    }
    return items;
  }
};

// --- semantic validation: every index and every enum that reaches Vulkan ----------------------------

bool in(uint32_t value, uint32_t low, uint32_t high) {
  return value >= low && value <= high;
}
bool valid_format(uint32_t f) {
  return f <= 184;
}  // the core formats of Vulkan 1.0 (all the packager writes)
bool valid_layout(uint32_t l) {
  return l <= 8 || l == 1000001002 || l == 1000117000 || l == 1000117001 || in(l, 1000241000, 1000241003) ||
         l == 1000314000 || l == 1000314001;
}
bool valid_samples(uint32_t s) {
  return std::has_single_bit(s) && s <= 64;
}
constexpr uint32_t kAllStages = 0x3F;  // VERTEX..COMPUTE

Result<void> validate_render_pass(const RenderPass& r) {
  auto what = [&] { return "render pass '" + r.name + "'"; };
  for (const auto& a : r.attachments)
    if (!valid_format(a.format) || !valid_samples(a.samples) || a.load_op > 2 || a.store_op > 1 ||
        a.stencil_load_op > 2 || a.stencil_store_op > 1 || !valid_layout(a.initial_layout) ||
        !valid_layout(a.final_layout))
      return corrupt(what() + " has an invalid attachment");
  if (r.subpasses.empty()) return corrupt(what() + " has no subpass");
  auto ref_ok = [&](const AttachmentRef& ref) {
    return (ref.attachment == kNone || ref.attachment < r.attachments.size()) && valid_layout(ref.layout);
  };
  for (const auto& s : r.subpasses) {
    for (const auto* list : {&s.inputs, &s.colors, &s.resolves})
      for (const auto& ref : *list)
        if (!ref_ok(ref)) return corrupt(what() + " has an invalid attachment reference");
    if (!ref_ok(s.depth_stencil)) return corrupt(what() + " has an invalid depth attachment reference");
    if (!s.resolves.empty() && s.resolves.size() != s.colors.size())
      return corrupt(what() + " has resolve attachments that do not match its color attachments");
    if (s.colors.size() > kMaxColorTargets) return corrupt(what() + " has more than 8 color attachments");
    for (uint32_t p : s.preserve)
      if (p >= r.attachments.size()) return corrupt(what() + " preserves a missing attachment");
  }
  for (const auto& d : r.dependencies)
    if ((d.src_subpass != kNone && d.src_subpass >= r.subpasses.size()) ||
        (d.dst_subpass != kNone && d.dst_subpass >= r.subpasses.size()))
      return corrupt(what() + " has a dependency on a missing subpass");
  return {};
}

Result<void> validate_graphics(const Contents& c, const Pipeline& p) {
  const GraphicsState& g = p.graphics;
  auto what = [&] { return "pipeline '" + p.name + "'"; };
  if (g.topology > 10 || g.polygon_mode > 2 || g.cull_mode > 3 || g.front_face > 1 || g.depth_compare > 7 ||
      !valid_samples(g.samples) || g.color_count > kMaxColorTargets || !valid_format(g.depth_stencil_format))
    return corrupt(what() + " has an invalid graphics state");
  for (float f : {g.depth_bias, g.depth_bias_clamp, g.depth_bias_slope})
    if (!std::isfinite(f)) return corrupt(what() + " has a depth bias that is not a finite number");
  // Vulkan guarantees patches of up to 32 control points (maxTessellationPatchSize); a patch list has a
  // count and nothing else does.
  if (g.patch_control_points > 32 || (g.topology == kTopologyPatchList) != (g.patch_control_points != 0))
    return corrupt(what() +
                   " has a patch list topology without patch control points (1 to 32), or the reverse");
  for (const auto* s : {&g.front, &g.back})
    if (s->fail_op > 7 || s->pass_op > 7 || s->depth_fail_op > 7 || s->compare_op > 7)
      return corrupt(what() + " has an invalid stencil state");
  for (uint32_t i = 0; i < kMaxColorTargets; ++i) {
    const BlendAttachment& b = g.blend[i];
    if (!valid_format(g.color_formats[i]) || b.src_color > 18 || b.dst_color > 18 || b.src_alpha > 18 ||
        b.dst_alpha > 18 || b.color_op > 4 || b.alpha_op > 4 || b.write_mask > 0xF)
      return corrupt(what() + " has an invalid render target " + std::to_string(i));
  }
  for (const auto& b : g.vertex_bindings)
    if (b.input_rate > 1) return corrupt(what() + " has an invalid vertex input rate");
  for (const auto& a : g.vertex_attributes) {
    if (!valid_format(a.format)) return corrupt(what() + " has an invalid vertex format");
    if (std::none_of(g.vertex_bindings.begin(), g.vertex_bindings.end(),
                     [&](const VertexBinding& b) { return b.binding == a.binding; }))
      return corrupt(what() + " has a vertex attribute without its binding");
  }
  if (p.render_pass != kNone) {
    if (p.render_pass >= c.render_passes.size()) return corrupt(what() + " refers to a missing render pass");
    if (p.subpass >= c.render_passes[p.render_pass].subpasses.size())
      return corrupt(what() + " refers to a missing subpass");
  }
  return {};
}

// Specialization constants of one pipeline: named, for a stage it has, 4 or 8 bytes, each once per stage.
Result<void> validate_constants(const std::string& pipeline, const std::vector<SpecConstant>& constants,
                                uint32_t stages) {
  std::set<std::pair<uint32_t, uint32_t>> ids;            // (stage, constant id)
  std::set<std::pair<uint32_t, std::string_view>> names;  // (stage, name): linear-log, not quadratic
  for (const SpecConstant& s : constants) {
    auto what = [&] { return "pipeline '" + pipeline + "': specialization constant '" + s.name + "'"; };
    if (s.name.empty() || !std::has_single_bit(s.stage) || (s.stage & stages) == 0)
      return corrupt(what() + " has no name or names a stage the pipeline lacks");
    if ((s.size != 4 && s.size != 8) || (s.size == 4 && (s.value >> 32) != 0))
      return corrupt(what() + " has an invalid size");
    if (!ids.emplace(s.stage, s.constant_id).second || !names.emplace(s.stage, s.name).second)
      return corrupt(what() + " is given twice for one stage");
  }
  return {};
}

// An OpenGL pipeline: sorted unique name, its stages, its bindings (each namespace's numbers used once),
// its graphics state as a Vulkan pipeline's (the same enumerations reach glEnable & co.).
Result<void> validate_gl_pipeline(const Contents& c, size_t i) {
  const GlPipeline& p = c.gl_pipelines[i];
  auto what = [&] { return "OpenGL pipeline '" + p.name + "'"; };
  if (i > 0 && c.gl_pipelines[i - 1].name >= p.name)
    return corrupt(what() + " breaks the sorted, unique name index");
  if (p.kind != PipelineKind::graphics && p.kind != PipelineKind::compute)
    return corrupt(what() + " has an unknown kind");
  uint32_t stages = 0;
  constexpr uint32_t kTessellationStages = 0x2 | 0x4;
  for (const GlShader& s : p.shaders) {
    if (!std::has_single_bit(s.stage) || (s.stage & kAllStages) == 0 || (stages & s.stage))
      return corrupt(what() + " has a shader with an invalid or repeated stage");
    if (s.blob >= c.spirv.size()) return corrupt(what() + " refers to a missing SPIR-V blob");
    stages |= s.stage;
  }
  constexpr uint32_t kComputeStage = 0x20, kVertexStage = 0x1;
  if (p.kind == PipelineKind::compute && stages != kComputeStage)
    return corrupt(what() + " is a compute pipeline without exactly one compute shader");
  if (p.kind == PipelineKind::graphics && (!(stages & kVertexStage) || (stages & kComputeStage)))
    return corrupt(what() + " needs a vertex shader and no compute shader");
  std::set<std::string_view> names;
  for (size_t k = 0; k < p.bindings.size(); ++k) {
    const GlBinding& b = p.bindings[k];
    if (b.kind >= kGlNamespaceCount || b.count == 0 || b.count > 1024 || (b.stages & ~kAllStages) != 0 ||
        (b.stages & stages) == 0)
      return corrupt(what() + ": binding '" + b.name + "' has an invalid kind, count or stages");
    if (!names.insert(b.name).second) return corrupt(what() + ": binding '" + b.name + "' is listed twice");
    // Sorted by (kind, binding), each range after the one before: lookups can search, nothing overlaps.
    const GlBinding* before = k > 0 ? &p.bindings[k - 1] : nullptr;
    if (before && (before->kind > b.kind ||
                   (before->kind == b.kind && uint64_t(before->binding) + before->count > b.binding)))
      return corrupt(what() + ": binding '" + b.name + "' is out of order or overlaps another of its kind");
  }
  if (auto valid = validate_constants(p.name, p.constants, stages); !valid) return valid;
  for (const SpecConstant& s : p.constants)  // glSpecializeShader takes 32-bit values
    if (s.size != 4) return corrupt(what() + ": specialization constant '" + s.name + "' is not 32-bit");
  if (p.kind == PipelineKind::graphics) {
    // Both tessellation stages (as the Vulkan pipeline it comes from) exactly when it draws patches.
    const uint32_t tessellation = stages & kTessellationStages;
    if ((tessellation != 0 || p.graphics.topology == kTopologyPatchList) &&
        (tessellation != kTessellationStages || p.graphics.topology != kTopologyPatchList))
      return corrupt(what() + " needs both tessellation stages and a patch list topology together");
    Pipeline as_vulkan;  // the same rules as a Vulkan pipeline's state without a render pass
    as_vulkan.name = p.name;
    as_vulkan.graphics = p.graphics;
    if (auto valid = validate_graphics(c, as_vulkan); !valid) return valid;
  }
  return {};
}

Result<void> validate(const Contents& c) {
  for (const Shader& s : c.shaders) {
    if (!std::has_single_bit(s.stage) || (s.stage & kAllStages) == 0)
      return corrupt("shader '" + s.name + "' has an invalid stage");
    if (s.blob >= c.spirv.size()) return corrupt("shader '" + s.name + "' refers to a missing SPIR-V blob");
    if (s.entry_point.empty()) return corrupt("shader '" + s.name + "' has no entry point");
  }
  for (size_t i = 0; i < c.standalone_shaders.size(); ++i) {
    uint32_t s = c.standalone_shaders[i];
    if (s >= c.shaders.size()) return corrupt("standalone shader index out of range");
    if (i > 0 && c.shaders[c.standalone_shaders[i - 1]].name >= c.shaders[s].name)
      return corrupt("standalone shader '" + c.shaders[s].name + "' breaks the sorted, unique name index");
  }
  for (const Sampler& s : c.samplers)
    if (s.mag_filter > 1 || s.min_filter > 1 || s.mipmap_mode > 1 || s.address_u > 4 || s.address_v > 4 ||
        s.address_w > 4 || s.compare_op > 7 || s.border_color > 5)
      return corrupt("a sampler has an invalid filter, address mode, comparison or border color");
  for (const SetLayout& layout : c.set_layouts) {
    for (size_t i = 0; i < layout.bindings.size(); ++i) {
      const Binding& b = layout.bindings[i];
      if (b.descriptor_type > 10) return corrupt("binding '" + b.name + "' has an unknown descriptor type");
      if ((b.stage_flags & ~kAllStages) != 0) return corrupt("binding '" + b.name + "' has invalid stages");
      if (i > 0 && layout.bindings[i - 1].binding >= b.binding)
        return corrupt("binding '" + b.name + "' is out of order or duplicated");
      if (b.immutable_sampler != kNone && (b.immutable_sampler >= c.samplers.size() || b.descriptor_type > 1))
        return corrupt("binding '" + b.name + "' has an invalid immutable sampler");
    }
  }
  for (const RenderPass& r : c.render_passes)
    if (auto valid = validate_render_pass(r); !valid) return valid;
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
    constexpr uint32_t kComputeStage = 0x20, kVertexStage = 0x1;
    if (p.kind == PipelineKind::compute && stages != kComputeStage)
      return corrupt("compute pipeline '" + p.name + "' needs exactly one compute shader");
    if (p.kind == PipelineKind::graphics && (!(stages & kVertexStage) || (stages & kComputeStage)))
      return corrupt("graphics pipeline '" + p.name + "' needs a vertex shader and no compute shader");
    for (uint32_t l : p.set_layouts)
      if (l != kNone && l >= c.set_layouts.size())
        return corrupt("pipeline '" + p.name + "' refers to a missing set layout");
    if ((p.push_constant_stages & ~kAllStages) != 0 || p.push_constant_size % 4 != 0)
      return corrupt("pipeline '" + p.name + "' has invalid push constants");
    if (p.kind == PipelineKind::compute ? p.dynamic_states != 0
                                        : (p.dynamic_states & ~kDynamicAllowed) != 0 ||
                                              (p.dynamic_states & kDynamicLegacy) != kDynamicLegacy)
      return corrupt("pipeline '" + p.name + "' has invalid dynamic states");
    if (auto valid = validate_constants(p.name, p.constants, stages); !valid) return valid;
    if (p.kind == PipelineKind::graphics)
      if (auto valid = validate_graphics(c, p); !valid) return valid;
  }
  return {};
}

uint64_t archive_checksum(std::span<const uint8_t> file) {
  XXH3_state_t state;
  XXH3_64bits_reset(&state);
  XXH3_64bits_update(&state, file.data(), kChecksumOffset);
  const uint8_t zeros[8] = {};
  XXH3_64bits_update(&state, zeros, sizeof zeros);
  XXH3_64bits_update(&state, file.data() + kChecksumOffset + 8, file.size() - kChecksumOffset - 8);
  return XXH3_64bits_digest(&state);
}

}  // namespace

Result<void> validate_gl(const Contents& c) {
  if (!c.gl_pipelines.empty() && !(c.backends & kBackendOpenGL))
    return corrupt("OpenGL pipelines in an archive whose header names no OpenGL backend");
  for (size_t i = 0; i < c.gl_pipelines.size(); ++i)
    if (auto valid = validate_gl_pipeline(c, i); !valid) return valid;
  return {};
}

template <class T>
std::string record_key(const T& record) {
  T copy = record;  // the visitors take mutable references
  KeyWriter key;
  visit(key, copy);
  return std::move(key.out);
}
template std::string record_key(const Shader&);
template std::string record_key(const Sampler&);
template std::string record_key(const SetLayout&);
template std::string record_key(const RenderPass&);

const char* descriptor_type_name(uint32_t type) {
  static constexpr const char* kNames[] = {"sampler",
                                           "combined image sampler",
                                           "sampled image",
                                           "storage image",
                                           "uniform texel buffer",
                                           "storage texel buffer",
                                           "uniform buffer",
                                           "storage buffer",
                                           "dynamic uniform buffer",
                                           "dynamic storage buffer",
                                           "input attachment"};
  return type < std::size(kNames) ? kNames[type] : "unknown descriptor";
}

std::optional<GlNamespace> gl_namespace_of(uint32_t descriptor_type) {
  switch (descriptor_type) {
    case 6:  // VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER
    case 8:  // VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER_DYNAMIC
      return GlNamespace::uniform_buffer;
    case 7:  // VK_DESCRIPTOR_TYPE_STORAGE_BUFFER
    case 9:  // VK_DESCRIPTOR_TYPE_STORAGE_BUFFER_DYNAMIC
      return GlNamespace::storage_buffer;
    case 1:  // VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER
    case 4:  // VK_DESCRIPTOR_TYPE_UNIFORM_TEXEL_BUFFER
      return GlNamespace::texture;
    case 3:  // VK_DESCRIPTOR_TYPE_STORAGE_IMAGE
    case 5:  // VK_DESCRIPTOR_TYPE_STORAGE_TEXEL_BUFFER
      return GlNamespace::image;
  }
  return std::nullopt;
}

const char* gl_namespace_name(uint32_t kind) {
  static constexpr const char* kNames[kGlNamespaceCount] = {"uniform buffer", "storage buffer", "texture",
                                                            "image"};
  return kind < kGlNamespaceCount ? kNames[kind] : "unknown";
}

uint64_t hash_bytes(std::span<const uint8_t> bytes) {
  return XXH3_64bits(bytes.data(), bytes.size());
}

// Records sorted by name: their order is sorted first, then each is moved once (a pipeline record is
// large, and sorting the records themselves moved each one log n times).
template <class Record>
void sort_by_name(std::vector<Record>& records) {
  std::vector<size_t> order(records.size());
  for (size_t i = 0; i < order.size(); ++i) order[i] = i;
  std::sort(order.begin(), order.end(),
            [&](size_t a, size_t b) { return records[a].name < records[b].name; });
  std::vector<Record> sorted;
  sorted.reserve(records.size());
  for (size_t i : order) sorted.push_back(std::move(records[i]));
  records = std::move(sorted);
}

std::vector<uint8_t> encode(const Contents& input) {
  Contents c = input;  // the visitors take mutable references
  sort_by_name(c.pipelines);
  std::sort(c.standalone_shaders.begin(), c.standalone_shaders.end(),
            [&](uint32_t a, uint32_t b) { return c.shaders[a].name < c.shaders[b].name; });
  sort_by_name(c.gl_pipelines);

  // Top-level records first, in index order, so their indices are what other records refer to.
  Writer w;
  for (auto& s : c.shaders) w.append(s);
  for (auto& s : c.samplers) w.append(s);
  for (auto& s : c.set_layouts) w.append(s);
  for (auto& r : c.render_passes) w.append(r);
  for (auto& p : c.pipelines) w.append(p);
  for (auto& p : c.pipelines) {
    PipelineExtras extras{p.kind == PipelineKind::graphics ? p.dynamic_states : 0, p.constants};
    w.append(extras);
  }
  const bool tessellation = append_patch_control_points<PipelineTessellation>(w, c.pipelines);
  for (auto& p : c.gl_pipelines) w.append(p);  // before the pools are laid out: it adds GFXS and SPEC
  const bool gl_tessellation = append_patch_control_points<GlPipelineTessellation>(w, c.gl_pipelines);

  struct SectionOut {
    uint32_t tag;
    std::vector<uint8_t> bytes;
    uint32_t count;
  };
  std::vector<SectionOut> sections;
  sections.push_back({kTagStrings, std::move(w.strings), 0});
  sections.push_back({kTagBlobs, std::vector<uint8_t>(c.spirv.size() * 16), uint32_t(c.spirv.size())});
  sections.push_back({kTagIndices, std::move(w.pools[kTagIndices].bytes), w.pools[kTagIndices].count});
  std::vector<uint8_t> standalone;
  for (uint32_t s : c.standalone_shaders) put_u32(standalone, s);
  sections.push_back({kTagStandalone, std::move(standalone), uint32_t(c.standalone_shaders.size())});
  for_each_record_type([&](auto record) {
    PoolOut& pool = w.pools[Tag<decltype(record)>::value];
    sections.push_back({Tag<decltype(record)>::value, std::move(pool.bytes), pool.count});
  });
  for (uint32_t tag : {Tag<PipelineExtras>::value, Tag<SpecConstant>::value}) {
    PoolOut& pool = w.pools[tag];
    sections.push_back({tag, std::move(pool.bytes), pool.count});
  }
  if (tessellation) {
    PoolOut& pool = w.pools[Tag<PipelineTessellation>::value];
    sections.push_back({Tag<PipelineTessellation>::value, std::move(pool.bytes), pool.count});
  }
  if (!c.gl_pipelines.empty())
    for_each_gl_record_type([&](auto record) {
      PoolOut& pool = w.pools[Tag<decltype(record)>::value];
      sections.push_back({Tag<decltype(record)>::value, std::move(pool.bytes), pool.count});
    });
  if (gl_tessellation) {
    PoolOut& pool = w.pools[Tag<GlPipelineTessellation>::value];
    sections.push_back({Tag<GlPipelineTessellation>::value, std::move(pool.bytes), pool.count});
  }
  sections.push_back({kTagData, {}, 0});

  // Lay out: header, section table, sections, then DATA with 16-byte aligned blobs.
  auto align = [](size_t v, size_t a) { return (v + a - 1) / a * a; };
  std::vector<uint32_t> offsets(sections.size());
  size_t cursor = kHeaderSize + sections.size() * 16;
  for (size_t i = 0; i + 1 < sections.size(); ++i) {
    cursor = align(cursor, 4);
    offsets[i] = uint32_t(cursor);
    cursor += sections[i].bytes.size();
  }
  const size_t data_start = align(cursor, kBlobAlignment);
  offsets.back() = uint32_t(data_start);
  std::vector<uint8_t>& data = sections.back().bytes;
  std::vector<uint8_t> blob_table;
  size_t data_bytes = 0;  // sized once: growing by each blob copied the whole DATA section again and again
  for (auto blob : c.spirv) data_bytes = align(data_bytes, kBlobAlignment) + blob.size_bytes();
  data.reserve(data_bytes);
  blob_table.reserve(c.spirv.size() * 16);
  for (auto blob : c.spirv) {
    data.resize(align(data.size(), kBlobAlignment));
    const auto* first = reinterpret_cast<const uint8_t*>(blob.data());
    put_u32(blob_table, uint32_t(data_start + data.size()));
    put_u32(blob_table, uint32_t(blob.size_bytes()));
    put_u64(blob_table, hash_bytes({first, blob.size_bytes()}));
    data.insert(data.end(), first, first + blob.size_bytes());
  }
  sections[1].bytes = std::move(blob_table);

  std::vector<uint8_t> out;
  out.reserve(data_start + data.size());
  out.insert(out.end(), kMagic.begin(), kMagic.end());
  put_u32(out, gl_tessellation ? kGlTessellationVersion : kWrittenVersion);
  put_u32(out, gl_tessellation ? kGlTessellationVersion
               : tessellation  ? kTessellationVersion
                               : kOldestReadableVersion);
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

namespace {

// The fixed 64-byte header, before anything it points at is read.
Result<void> check_header(std::span<const uint8_t> file) {
  if (reinterpret_cast<uintptr_t>(file.data()) % 4 != 0)
    return detail::failure(ErrorCode::misaligned_memory,
                           "archive memory must be 4-byte aligned to hand SPIR-V to Vulkan");
  if (file.size() >= kMagic.size() && !std::equal(kMagic.begin(), kMagic.end(), file.begin()))
    return detail::failure(ErrorCode::bad_magic, "not a statepack archive (wrong magic bytes)");
  if (file.size() < kHeaderSize)
    return detail::failure(ErrorCode::truncated, "truncated archive: " + std::to_string(file.size()) +
                                                     " bytes is shorter than the 64-byte header");
  const uint8_t* h = file.data();
  uint32_t version = get_u32(h + 8), oldest = get_u32(h + 12), header_size = get_u32(h + 16);
  if (oldest > kFormatVersion)
    return detail::failure(ErrorCode::unsupported_version,
                           "archive format version " + std::to_string(version) +
                               " needs a reader of version " + std::to_string(oldest) +
                               " or newer; this reader understands version " +
                               std::to_string(kFormatVersion));
  uint64_t file_size = get_u64(h + 32);
  if (file_size > file.size())
    return detail::failure(ErrorCode::truncated, "truncated archive: header says " +
                                                     std::to_string(file_size) + " bytes, got " +
                                                     std::to_string(file.size()));
  if (file_size < file.size())
    return corrupt("header says " + std::to_string(file_size) + " bytes but " + std::to_string(file.size()) +
                   " were given (trailing data)");
  // Fuzzing builds skip the hashes so that mutated inputs reach the structural checks behind them.
  if (!kFuzzing && archive_checksum(file) != get_u64(h + kChecksumOffset))
    return detail::failure(ErrorCode::checksum_mismatch, "archive checksum mismatch: the file is damaged");
  if (header_size < kHeaderSize || header_size > file.size()) return corrupt("bad header size");
  return {};
}

// The section table into r.sections; the header has been checked.
Result<void> read_section_table(std::span<const uint8_t> file, Reader& r) {
  const uint8_t* h = file.data();
  uint32_t header_size = get_u32(h + 16), section_count = get_u32(h + 48), table = get_u32(h + 52);
  if (table < header_size || table % 4 != 0 || uint64_t(table) + uint64_t(section_count) * 16 > file.size())
    return corrupt("section table outside the file");
  for (uint32_t i = 0; i < section_count; ++i) {
    const uint8_t* e = file.data() + table + 16 * i;
    Section s{get_u32(e + 4), get_u32(e + 8), get_u32(e + 12)};
    if (s.offset % 4 != 0 || uint64_t(s.offset) + s.size > file.size())
      return corrupt("section " + std::to_string(i) + " lies outside the file");
    if (!r.sections.emplace(get_u32(e), s).second)
      return corrupt("section " + std::to_string(i) + " is repeated");
  }
  return {};
}

// Section TAG is present and, when it holds records of RECORD bytes, exactly its count of them.
Result<void> check_section(const Reader& r, uint32_t tag, uint32_t record) {
  char name[5] = {char(tag), char(tag >> 8), char(tag >> 16), char(tag >> 24), 0};
  auto it = r.sections.find(tag);
  if (it == r.sections.end()) return corrupt(std::string("missing section ") + name);
  if (record != 0 && uint64_t(it->second.count) * record != it->second.size)
    return corrupt(std::string("section ") + name + " size does not match its record count");
  return {};
}

// The sections every format version has.
Result<void> check_required_sections(const Reader& r) {
  Result<void> ok;
  for (auto [tag, size] : {std::pair{kTagStrings, 0u},
                           {kTagData, 0u},
                           {kTagBlobs, 16u},
                           {kTagIndices, 4u},
                           {kTagStandalone, 4u}})
    if (ok = check_section(r, tag, size); !ok) return ok.error();
  for_each_record_type([&](auto record) {
    if (ok) ok = check_section(r, Tag<decltype(record)>::value, record_size<decltype(record)>());
  });
  return ok;
}

// Blobs: inside DATA, aligned, a whole number of SPIR-V words, content hash matching.
Result<void> read_spirv_blobs(std::span<const uint8_t> file, Reader& r, Contents& c) {
  const Section& data = r.sections[kTagData];
  const Section& blobs = r.sections[kTagBlobs];
  for (uint32_t i = 0; i < blobs.count; ++i) {
    const uint8_t* e = file.data() + blobs.offset + 16 * i;
    uint32_t offset = get_u32(e), size = get_u32(e + 4);
    if (offset % kBlobAlignment != 0 || size == 0 || size % 4 != 0 || offset < data.offset ||
        uint64_t(offset) + size > uint64_t(data.offset) + data.size)
      return corrupt("SPIR-V blob " + std::to_string(i) + " has a bad offset or size");
    std::span<const uint8_t> bytes = file.subspan(offset, size);
    if (!kFuzzing && hash_bytes(bytes) != get_u64(e + 8))
      return detail::failure(ErrorCode::checksum_mismatch,
                             "SPIR-V blob " + std::to_string(i) + " content hash mismatch");
    if (get_u32(bytes.data()) != kSpirvMagic) return corrupt("blob " + std::to_string(i) + " is not SPIR-V");
    c.spirv.emplace_back(reinterpret_cast<const uint32_t*>(bytes.data()), size / 4);
  }
  return {};
}

// Format 2's PEXT (with its SPEC pool), one record per pipeline; absent in format 1.
Result<void> read_pipeline_extras(Reader& r, Contents& c) {
  if (!r.sections.count(Tag<PipelineExtras>::value)) {
    for (auto& p : c.pipelines) p.dynamic_states = p.kind == PipelineKind::graphics ? kDynamicLegacy : 0;
    return {};
  }
  for (auto [tag, size] : {std::pair{Tag<PipelineExtras>::value, record_size<PipelineExtras>()},
                           std::pair{Tag<SpecConstant>::value, record_size<SpecConstant>()}})
    if (auto valid = check_section(r, tag, size); !valid) return valid.error();
  if (r.sections[Tag<PipelineExtras>::value].count != c.pipelines.size())
    return corrupt("section PEXT does not have one record per pipeline");
  std::vector<PipelineExtras> extras = r.all<PipelineExtras>("pipeline extension");
  for (size_t i = 0; i < extras.size() && !r.problem; ++i) {
    c.pipelines[i].dynamic_states = extras[i].dynamic_states;
    c.pipelines[i].constants = std::move(extras[i].constants);
  }
  return {};
}

// TESS (format 3) and GLTS (format 4): one record per pipeline of their list, present only when one
// of them tessellates.
template <class Record, class P>
Result<void> read_patch_control_points(Reader& r, std::vector<P>& pipelines, const char* section,
                                       const std::string& kind, const char* label) {
  if (!r.sections.count(Tag<Record>::value)) return {};
  if (auto valid = check_section(r, Tag<Record>::value, record_size<Record>()); !valid) return valid;
  if (r.sections[Tag<Record>::value].count != pipelines.size())
    return corrupt(std::string("section ") + section + " does not have one record per " + kind + "pipeline");
  std::vector<Record> points = r.all<Record>(label);
  for (size_t i = 0; i < points.size() && !r.problem; ++i) {
    if (pipelines[i].kind != PipelineKind::graphics && points[i].patch_control_points != 0)
      return corrupt(kind + "compute pipeline '" + pipelines[i].name + "' has patch control points");
    pipelines[i].graphics.patch_control_points = points[i].patch_control_points;
  }
  return {};
}

// The OpenGL block: all three sections or none. Its constants are in the SPEC pool, whose size is
// checked here too (an archive without PEXT has not checked it). Read once per archive with such a block,
// for statepack_gl, and compiled for size: a Vulkan program never needs it fast (issue 39).
[[gnu::cold]] Result<void> read_gl_records(Reader& r, Contents& c) {
  if (auto valid = check_section(r, Tag<SpecConstant>::value, record_size<SpecConstant>()); !valid)
    return valid.error();
  Result<void> present;
  for_each_gl_record_type([&](auto record) {
    if (present) present = check_section(r, Tag<decltype(record)>::value, record_size<decltype(record)>());
  });
  if (!present) return present.error();
  c.gl_pipelines = r.all<GlPipeline>("OpenGL pipeline");
  return read_patch_control_points<GlPipelineTessellation>(r, c.gl_pipelines, "GLTS", "OpenGL ",
                                                           "OpenGL tessellation");
}

Result<void> read_gl_block(Reader& r, Contents& c) {
  return r.sections.count(Tag<GlPipeline>::value) ? read_gl_records(r, c) : Result<void>{};
}

}  // namespace

Result<Contents> decode(std::span<const uint8_t> file) {
  if (auto valid = check_header(file); !valid) return valid.error();
  const uint8_t* h = file.data();
  Contents c;
  c.format_version = get_u32(h + 8);
  c.producer_version = get_u32(h + 20);
  c.content_version = get_u32(h + 24);
  c.backends = get_u32(h + 28);

  Reader r{file, {}};
  if (auto read = read_section_table(file, r); !read) return read.error();
  if (auto valid = check_required_sections(r); !valid) return valid.error();
  if (auto read = read_spirv_blobs(file, r, c); !read) return read.error();
  const Section& standalone = r.sections[kTagStandalone];
  for (uint32_t i = 0; i < standalone.count; ++i)
    c.standalone_shaders.push_back(get_u32(file.data() + standalone.offset + 4 * i));

  r.initial_budget = r.budget = uint64_t(file.size()) * kExpansionFactor + kExpansionSlack;
  c.shaders = r.all<Shader>("shader");
  c.samplers = r.all<Sampler>("sampler");
  c.set_layouts = r.all<SetLayout>("set layout");
  c.render_passes = r.all<RenderPass>("render pass");
  c.pipelines = r.all<Pipeline>("pipeline");
  if (auto read = read_pipeline_extras(r, c); !read) return read.error();
  if (auto read = read_patch_control_points<PipelineTessellation>(r, c.pipelines, "TESS", "",
                                                                  "pipeline tessellation");
      !read)
    return read.error();
  if (auto read = read_gl_block(r, c); !read) return read.error();
  if (r.problem) return corrupt(*r.problem);
  if (auto valid = validate(c); !valid) return valid.error();
  return c;
}

}  // namespace statepack::format
