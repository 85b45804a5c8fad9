// Archive format: round trip, determinism, a pinned format-3 file, and clean rejection of damaged bytes.
#include <gtest/gtest.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstring>
#include <fstream>
#include <map>
#include <set>

#include "format/archive_format.hpp"

namespace statepack::format {
namespace {

// Little-endian helpers to forge headers in tests.
void put_u32(std::vector<uint8_t>& bytes, size_t at, uint32_t v) {
  for (int i = 0; i < 4; ++i) bytes[at + i] = uint8_t(v >> (8 * i));
}
void put_u64(std::vector<uint8_t>& bytes, size_t at, uint64_t v) {
  for (int i = 0; i < 8; ++i) bytes[at + i] = uint8_t(v >> (8 * i));
}
// Recomputes the whole-archive checksum so a test can reach the structural checks behind it.
void reseal(std::vector<uint8_t>& bytes) {
  put_u64(bytes, 40, 0);
  put_u64(bytes, 40, hash_bytes(bytes));
}

// Aligned copy of bytes (decode needs 4-byte alignment).
struct Aligned {
  explicit Aligned(const std::vector<uint8_t>& bytes) : words((bytes.size() + 3) / 4), size(bytes.size()) {
    if (!bytes.empty()) std::memcpy(words.data(), bytes.data(), bytes.size());
  }
  std::span<const uint8_t> span() const { return {reinterpret_cast<const uint8_t*>(words.data()), size}; }
  std::vector<uint32_t> words;
  size_t size;
};

struct Fixture {
  std::vector<uint32_t> spirv_a{0x07230203, 0x00010000, 1, 2, 3};
  std::vector<uint32_t> spirv_b{0x07230203, 0x00010000, 4, 5, 6, 7};
  Contents contents;
  Fixture() {
    contents.producer_version = 42;
    contents.content_version = 7;
    contents.spirv = {spirv_a, spirv_b};
    contents.shaders = {{"VS", 0x1, 0, "main"}, {"PS", 0x10, 1, "ps_main"}, {"CS", 0x20, 1, "main"}};
    contents.standalone_shaders = {2, 0};
    Sampler sampler;
    sampler.address_u = 0;
    sampler.max_lod = 8.5f;
    contents.samplers = {sampler};
    SetLayout layout;
    layout.name = "Material";
    layout.binding_index = 1;
    layout.bindings = {{"cbConstants", 0, 6, 1, 0x11, kNone}, {"g_Texture", 2, 1, 4, 0x10, 0}};
    contents.set_layouts = {layout};
    RenderPass pass;
    pass.name = "Main";
    pass.attachments = {{37, 1, 1, 0, 2, 1, 0, 6}, {126, 1, 1, 1, 2, 1, 0, 3}};
    Subpass subpass;
    subpass.colors = {{0, 2}};
    subpass.depth_stencil = {1, 3};
    subpass.preserve = {};
    pass.subpasses = {subpass};
    pass.dependencies = {{0, kNone, 0x400, 0x1000, 0x100, 0x800, 0}};
    contents.render_passes = {pass};
    Pipeline graphics;
    graphics.name = "Zeta graphics";
    graphics.kind = PipelineKind::graphics;
    graphics.shaders = {0, 1};
    graphics.set_layouts = {kNone, 0};
    graphics.push_constant_size = 16;
    graphics.push_constant_stages = 0x1;
    graphics.graphics.color_count = 2;
    graphics.graphics.color_formats[0] = 37;
    graphics.graphics.color_formats[1] = 109;
    graphics.graphics.depth_bias_slope = 1.5f;
    graphics.graphics.blend[1].enable = 1;
    graphics.graphics.vertex_bindings = {{0, 20, 0}, {1, 16, 1}};
    graphics.graphics.vertex_attributes = {{0, 0, 106, 0}, {1, 0, 103, 12}, {2, 1, 109, 0}};
    graphics.render_pass = 0;
    graphics.subpass = 0;
    graphics.dynamic_states = kDynamicDefault | kDynamicLineWidth | (1u << kDynamicExtendedFirstBit);
    graphics.constants = {{"kTint", 0x10, 3, 4, 0x3F800000u}, {"kCount", 0x1, 0, 4, 7}};
    Pipeline compute;
    compute.name = "Alpha compute";
    compute.kind = PipelineKind::compute;
    compute.shaders = {2};
    compute.constants = {{"kScale", 0x20, 1, 8, 0x4000000000000000ull}};
    contents.pipelines = {graphics, compute};
    // The OpenGL block: every truncation and byte flip below reaches it too.
    contents.backends = kBackendVulkan | kBackendOpenGL;
    GlPipeline gl_graphics;
    gl_graphics.name = "Zeta graphics";
    gl_graphics.shaders = {{"VS", 0x1, 0, "main"}, {"PS", 0x10, 1, "main"}};
    gl_graphics.bindings = {{"cbConstants", 0, 0, 1, 0x11}, {"g_Texture", 2, 3, 4, 0x10}};
    gl_graphics.graphics = graphics.graphics;
    gl_graphics.constants = {{"kTint", 0x10, 3, 4, 0x3F800000u}};
    GlPipeline gl_compute;
    gl_compute.name = "Alpha compute";
    gl_compute.kind = PipelineKind::compute;
    gl_compute.shaders = {{"CS", 0x20, 1, "main"}};
    gl_compute.bindings = {{"Values", 1, 0, 1, 0x20}};
    contents.gl_pipelines = {gl_compute, gl_graphics};
  }
};

TEST(ArchiveFormat, OpenGlBlockRoundTripsAndIsAbsentWithoutGlPipelines) {
  Fixture f;
  auto bytes = encode(f.contents);
  Aligned aligned(bytes);
  auto decoded = decode(aligned.span());
  ASSERT_TRUE(decoded) << decoded.error().message;
  EXPECT_EQ(decoded->backends, kBackendVulkan | kBackendOpenGL);
  EXPECT_EQ(decoded->gl_pipelines, f.contents.gl_pipelines);
  EXPECT_EQ(decoded->pipelines.size(), 2u);  // the Vulkan part is unchanged beside it
  // Without GL pipelines no GLPI/GLSH/GLBD section is written, so Vulkan-only archives keep their bytes.
  auto has_tag = [](const std::vector<uint8_t>& b, const char* tag) {
    const uint32_t count =
        uint32_t(b[48]) | uint32_t(b[49]) << 8 | uint32_t(b[50]) << 16 | uint32_t(b[51]) << 24;
    for (uint32_t i = 0; i < count; ++i)
      if (std::memcmp(b.data() + 64 + 16 * i, tag, 4) == 0) return true;
    return false;
  };
  EXPECT_TRUE(has_tag(bytes, "GLPI") && has_tag(bytes, "GLSH") && has_tag(bytes, "GLBD"));
  f.contents.gl_pipelines.clear();
  f.contents.backends = kBackendVulkan;
  auto vulkan_only = encode(f.contents);
  EXPECT_FALSE(has_tag(vulkan_only, "GLPI") || has_tag(vulkan_only, "GLSH") || has_tag(vulkan_only, "GLBD"));
}

// GL constants live in the SPEC pool: its size is checked even when PEXT (which checks it otherwise) is
// gone. Before, a SPEC entry claiming 30000 records past the end made decoding read outside the file.
TEST(ArchiveFormat, OpenGlConstantsPoolIsCheckedWithoutPext) {
  Fixture f;
  auto bytes = encode(f.contents);
  const uint32_t count = uint32_t(bytes[48]) | uint32_t(bytes[49]) << 8;
  for (uint32_t i = 0; i < count; ++i) {
    uint8_t* e = bytes.data() + 64 + 16 * i;
    if (std::memcmp(e, "PEXT", 4) == 0) std::memcpy(e, "XEXT", 4);  // a tag nobody knows: ignored
    if (std::memcmp(e, "SPEC", 4) == 0) {
      put_u32(bytes, 64 + 16 * i + 4, uint32_t(bytes.size()));  // offset: the end of the file
      put_u32(bytes, 64 + 16 * i + 8, 0);                       // size 0
      put_u32(bytes, 64 + 16 * i + 12, 30000);                  // but 30000 records
    }
  }
  reseal(bytes);
  Aligned aligned(bytes);
  auto decoded = decode(aligned.span());  // ASan fails this test on any read outside the file
  ASSERT_FALSE(decoded);
  EXPECT_NE(decoded.error().message.find("section SPEC size does not match its record count"),
            std::string::npos)
      << decoded.error().message;
}

TEST(ArchiveFormat, OpenGlPipelinesAreValidated) {
  auto refused = [](auto edit) {
    Fixture f;
    edit(f.contents);
    auto bytes = encode(f.contents);
    Aligned aligned(bytes);
    auto decoded = decode(aligned.span());  // the OpenGL records are validate_gl's, not decode's
    if (!decoded) return decoded.error().message;
    auto valid = validate_gl(*decoded);
    return valid ? std::string("accepted") : valid.error().message;
  };
  EXPECT_EQ(refused([](Contents&) {}), "accepted");
  EXPECT_NE(refused([](Contents& c) { c.backends = kBackendVulkan; }).find("names no OpenGL backend"),
            std::string::npos);
  EXPECT_NE(refused([](Contents& c) { c.gl_pipelines[1].shaders[0].blob = 9; }).find("missing SPIR-V blob"),
            std::string::npos);
  EXPECT_NE(refused([](Contents& c) { c.gl_pipelines[1].bindings[1].kind = 7; }).find("invalid kind"),
            std::string::npos);
  EXPECT_NE(refused([](Contents& c) {
              c.gl_pipelines[1].bindings[1] = {"g_Texture", 0, 0, 1, 0x10};  // binding 0 of UBOs, twice
            }).find("overlaps"),
            std::string::npos);
  EXPECT_NE(refused([](Contents& c) {
              c.gl_pipelines[1].shaders.pop_back();
              c.gl_pipelines[1].shaders[0].stage = 0x20;
            }).find("needs a vertex shader"),
            std::string::npos);
  EXPECT_NE(
      refused([](Contents& c) { c.gl_pipelines[1].graphics.topology = 99; }).find("invalid graphics state"),
      std::string::npos);
  EXPECT_NE(refused([](Contents& c) {
              c.gl_pipelines[1].constants[0] = {"kTint", 0x10, 3, 8, 1};
            }).find("not 32-bit"),
            std::string::npos);
  EXPECT_NE(refused([](Contents& c) {
              c.gl_pipelines[1].shaders.push_back({"TCS", 0x2, 0, "main"});
            }).find("tessellation"),
            std::string::npos);
}

TEST(ArchiveFormat, RoundTripKeepsEveryField) {
  Fixture f;
  auto bytes = encode(f.contents);
  Aligned aligned(bytes);
  auto decoded = decode(aligned.span());
  ASSERT_TRUE(decoded) << decoded.error().message;
  const Contents& c = *decoded;
  EXPECT_EQ(c.format_version, kWrittenVersion);
  EXPECT_EQ(c.producer_version, 42u);
  EXPECT_EQ(c.content_version, 7u);
  ASSERT_EQ(c.spirv.size(), 2u);
  EXPECT_TRUE(std::ranges::equal(c.spirv[1], f.spirv_b));
  for (auto blob : c.spirv) EXPECT_EQ(reinterpret_cast<uintptr_t>(blob.data()) % kBlobAlignment, 0u);
  ASSERT_EQ(c.shaders.size(), 3u);
  EXPECT_EQ(c.shaders[1].entry_point, "ps_main");
  EXPECT_EQ(c.shaders[1].stage, 0x10u);
  ASSERT_EQ(c.set_layouts.size(), 1u);
  EXPECT_EQ(c.set_layouts[0], f.contents.set_layouts[0]);
  EXPECT_EQ(c.samplers, f.contents.samplers);
  EXPECT_EQ(c.render_passes, f.contents.render_passes);
  // Standalone shaders come back sorted by name: CS, VS.
  EXPECT_EQ(c.standalone_shaders, (std::vector<uint32_t>{2, 0}));
  ASSERT_EQ(c.pipelines.size(), 2u);
  // Pipelines come back sorted by name: the name index is the pipeline table itself.
  EXPECT_EQ(c.pipelines[0].name, "Alpha compute");
  EXPECT_EQ(c.pipelines[0].kind, PipelineKind::compute);
  const Pipeline& g = c.pipelines[1];
  EXPECT_EQ(g.name, "Zeta graphics");
  EXPECT_EQ(g.shaders, (std::vector<uint32_t>{0, 1}));
  EXPECT_EQ(g.set_layouts, (std::vector<uint32_t>{kNone, 0}));
  EXPECT_EQ(g.push_constant_size, 16u);
  EXPECT_EQ(g.graphics, f.contents.pipelines[0].graphics);
  // Format 2: dynamic states and specialization constants (values with all their bytes).
  EXPECT_EQ(g.dynamic_states, f.contents.pipelines[0].dynamic_states);
  EXPECT_EQ(g.constants, f.contents.pipelines[0].constants);
  EXPECT_EQ(c.pipelines[0].dynamic_states, 0u);  // compute pipelines have none
  EXPECT_EQ(c.pipelines[0].constants, f.contents.pipelines[1].constants);
}

// An archive of format 1 (no PEXT/SPEC sections) still reads: viewport and scissor dynamic, no constants.
TEST(ArchiveFormat, FormatOneArchivesStillRead) {
  Fixture f;
  f.contents.gl_pipelines.clear();  // format 1 had no OpenGL block (it would refer to the SPEC pool)
  f.contents.backends = kBackendVulkan;
  auto bytes = encode(f.contents);
  auto u32 = [&](size_t at) {
    return uint32_t(bytes[at]) | uint32_t(bytes[at + 1]) << 8 | uint32_t(bytes[at + 2]) << 16 |
           uint32_t(bytes[at + 3]) << 24;
  };
  // Drop the PEXT and SPEC entries from the section table (their bytes stay, unreferenced).
  const uint32_t count = u32(48);
  std::vector<std::array<uint8_t, 16>> kept;
  for (uint32_t i = 0; i < count; ++i) {
    std::array<uint8_t, 16> entry;
    std::copy_n(bytes.begin() + 64 + 16 * i, 16, entry.begin());
    const std::string tag(entry.begin(), entry.begin() + 4);
    if (tag != "PEXT" && tag != "SPEC") kept.push_back(entry);
  }
  ASSERT_EQ(kept.size(), count - 2);
  for (size_t i = 0; i < kept.size(); ++i)
    std::copy(kept[i].begin(), kept[i].end(), bytes.begin() + 64 + 16 * i);
  put_u32(bytes, 48, count - 2);
  put_u32(bytes, 8, 1);   // format_version
  put_u32(bytes, 12, 1);  // oldest_readable_version
  reseal(bytes);
  Aligned aligned(bytes);
  auto decoded = decode(aligned.span());
  ASSERT_TRUE(decoded) << decoded.error().message;
  EXPECT_EQ(decoded->format_version, 1u);
  EXPECT_EQ(decoded->pipelines[1].dynamic_states, kDynamicLegacy);
  EXPECT_TRUE(decoded->pipelines[1].constants.empty());
  EXPECT_EQ(decoded->pipelines[0].dynamic_states, 0u);
}

// docs/archive-format.md gives every record's size in its section table: read from the document itself
// (rows "| TAG | ... | SIZE |"), so a section added to the format without a row, or a size that changed,
// fails here. Every section with a size must appear in one of the encodings below.
std::map<std::string, uint32_t> record_sizes_from_spec() {
  std::ifstream doc(STATEPACK_ARCHIVE_FORMAT_DOC);
  EXPECT_TRUE(doc) << STATEPACK_ARCHIVE_FORMAT_DOC;
  std::map<std::string, uint32_t> sizes;
  for (std::string line; std::getline(doc, line);) {
    if (line.size() < 8 || line.rfind("| ", 0) != 0 || line[6] != ' ' || line[7] != '|') continue;
    const std::string tag = line.substr(2, 4);
    if (!std::all_of(tag.begin(), tag.end(), [](char c) { return c >= 'A' && c <= 'Z'; })) continue;
    const size_t last = line.rfind('|', line.size() - 2);
    const std::string size = line.substr(last + 1, line.size() - last - 2);
    const std::string digits = size.substr(size.find_first_not_of(' '),
                                           size.find_last_not_of(' ') - size.find_first_not_of(' ') + 1);
    if (!digits.empty() &&
        std::all_of(digits.begin(), digits.end(), [](unsigned char c) { return std::isdigit(c) != 0; }))
      sizes[tag] = uint32_t(std::stoul(digits));  // STRS and DATA are raw bytes ("—")
  }
  return sizes;
}

TEST(ArchiveFormat, SectionRecordSizesMatchTheSpec) {
  const std::map<std::string, uint32_t> spec = record_sizes_from_spec();
  ASSERT_GE(spec.size(), 22u) << "the section table of docs/archive-format.md was not found";
  Fixture plain;
  Fixture tessellated;  // adds TESS and GLTS
  for (auto& p : tessellated.contents.pipelines)
    if (p.kind == PipelineKind::graphics) p.graphics.topology = 10, p.graphics.patch_control_points = 3;
  for (auto& p : tessellated.contents.gl_pipelines)
    if (p.kind == PipelineKind::graphics) p.graphics.topology = 10, p.graphics.patch_control_points = 3;
  std::set<std::string> seen;
  for (const Fixture* f : {&plain, &tessellated}) {
    auto bytes = encode(f->contents);
    auto u32 = [&](size_t at) {
      return uint32_t(bytes[at]) | uint32_t(bytes[at + 1]) << 8 | uint32_t(bytes[at + 2]) << 16 |
             uint32_t(bytes[at + 3]) << 24;
    };
    for (uint32_t i = 0; i < u32(48); ++i) {
      size_t entry = u32(52) + 16 * i;
      std::string tag(reinterpret_cast<const char*>(&bytes[entry]), 4);
      seen.insert(tag);
      if (tag == "STRS" || tag == "DATA") continue;
      ASSERT_TRUE(spec.count(tag)) << "section " << tag << " has no row in docs/archive-format.md";
      EXPECT_EQ(u32(entry + 8), u32(entry + 12) * spec.at(tag)) << tag;
    }
  }
  for (const auto& [tag, size] : spec) EXPECT_TRUE(seen.count(tag)) << "section " << tag << " never written";
}

TEST(ArchiveFormat, EncodingIsDeterministicAndOrderIndependent) {
  Fixture f;
  auto first = encode(f.contents);
  std::swap(f.contents.pipelines[0], f.contents.pipelines[1]);
  EXPECT_EQ(encode(f.contents), first);
}

TEST(ArchiveFormat, EveryTruncationIsRejected) {
  Fixture f;
  auto bytes = encode(f.contents);
  for (size_t size = 0; size < bytes.size(); ++size) {
    std::vector<uint8_t> cut(bytes.begin(), bytes.begin() + size);
    Aligned aligned(cut);
    auto decoded = decode(aligned.span());
    ASSERT_FALSE(decoded) << "accepted a file cut to " << size << " bytes";
    EXPECT_TRUE(decoded.error().code == ErrorCode::truncated || decoded.error().code == ErrorCode::bad_magic)
        << size << ": " << decoded.error().message;
  }
}

TEST(ArchiveFormat, EverySingleByteFlipIsRejected) {
  Fixture f;
  auto bytes = encode(f.contents);
  for (size_t i = 0; i < bytes.size(); ++i) {
    for (uint8_t mask : {uint8_t(0x01), uint8_t(0x80)}) {
      auto damaged = bytes;
      damaged[i] ^= mask;
      Aligned aligned(damaged);
      auto decoded = decode(aligned.span());
      ASSERT_FALSE(decoded) << "accepted a flip of byte " << i;
    }
  }
}

// Behind the checksum: forged but resealed headers and tables must still be caught, never crash.
TEST(ArchiveFormat, ResealedStructuralDamageIsRejected) {
  Fixture f;
  const auto bytes = encode(f.contents);
  size_t rejected = 0, total = 0;
  for (size_t i = 0; i < bytes.size(); ++i) {
    for (uint8_t value : {uint8_t(0x00), uint8_t(0xFF), uint8_t(0x7F)}) {
      if (bytes[i] == value) continue;
      auto damaged = bytes;
      damaged[i] = value;
      if (i < 40 || i >= 48) reseal(damaged);
      Aligned aligned(damaged);
      auto decoded = decode(aligned.span());  // must return, whatever it decides
      ++total;
      rejected += !decoded;
    }
  }
  // Most resealed damage is structural; some (a name letter, a blend factor) is legal content.
  EXPECT_GT(rejected, total / 3) << rejected << " of " << total;
}

TEST(ArchiveFormat, NewerFormatIsRefusedWithVersions) {
  Fixture f;
  auto bytes = encode(f.contents);
  put_u32(bytes, 8, kFormatVersion + 2);   // format_version
  put_u32(bytes, 12, kFormatVersion + 1);  // oldest_readable_version
  reseal(bytes);
  Aligned aligned(bytes);
  auto decoded = decode(aligned.span());
  ASSERT_FALSE(decoded);
  EXPECT_EQ(decoded.error().code, ErrorCode::unsupported_version);
  const std::string expected = "version " + std::to_string(kFormatVersion + 2) +
                               " needs a reader of version " + std::to_string(kFormatVersion + 1) +
                               " or newer";
  EXPECT_NE(decoded.error().message.find(expected), std::string::npos) << decoded.error().message;
}

uint32_t oldest_readable(const std::vector<uint8_t>& bytes) {
  return uint32_t(bytes[12]) | uint32_t(bytes[13]) << 8 | uint32_t(bytes[14]) << 16 |
         uint32_t(bytes[15]) << 24;
}

// Patch control points live in format 3's TESS section, written only when a pipeline tessellates: other
// archives stay readable by version-2 readers.
TEST(ArchiveFormat, PatchControlPointsRoundTripAndNeedAVersion3Reader) {
  Fixture f;
  auto plain = encode(f.contents);
  EXPECT_EQ(oldest_readable(plain), 2u);
  EXPECT_EQ(std::search(plain.begin(), plain.end(), std::begin("TESS"), std::end("TESS") - 1), plain.end());

  f.contents.pipelines[0].graphics.topology = 10;  // VK_PRIMITIVE_TOPOLOGY_PATCH_LIST
  f.contents.pipelines[0].graphics.patch_control_points = 4;
  auto bytes = encode(f.contents);
  EXPECT_EQ(oldest_readable(bytes), 3u);
  Aligned aligned(bytes);
  auto decoded = decode(aligned.span());
  ASSERT_TRUE(decoded) << decoded.error().message;
  const Pipeline* tessellated = nullptr;
  for (const Pipeline& p : decoded->pipelines)
    if (p.name == "Zeta graphics") tessellated = &p;
  ASSERT_NE(tessellated, nullptr);
  EXPECT_EQ(tessellated->graphics.topology, 10u);
  EXPECT_EQ(tessellated->graphics.patch_control_points, 4u);
  for (const Pipeline& p : decoded->pipelines) {
    if (&p != tessellated) {
      EXPECT_EQ(p.graphics.patch_control_points, 0u);
    }
  }
}

TEST(ArchiveFormat, PatchListsNeedOneToThirtyTwoControlPoints) {
  for (auto [topology, points] : {std::pair{10u, 0u}, {10u, 33u}, {3u, 3u}}) {
    Fixture f;
    f.contents.pipelines[0].graphics.topology = topology;
    f.contents.pipelines[0].graphics.patch_control_points = points;
    auto bytes = encode(f.contents);
    Aligned aligned(bytes);
    auto decoded = decode(aligned.span());
    ASSERT_FALSE(decoded) << topology << " " << points;
    EXPECT_NE(decoded.error().message.find("patch control points"), std::string::npos)
        << decoded.error().message;
  }
}

// A committed archive (tests/data/pinned, made by `statepack merge` of six corpus archives: render pass,
// signatures with an immutable sampler, specialization constants, dynamic states, tessellation) must
// decode, and encode back to the same bytes: a field reordered in a visit() or a changed section layout
// fails here, where a round trip of this code's own output would not. Its decoded contents are pinned
// by inspect's JSON in the CLI tests.
TEST(ArchiveFormat, PinnedFormat3FileDecodesAndReencodesByteForByte) {
  std::ifstream in(STATEPACK_PINNED_ARCHIVE, std::ios::binary);
  ASSERT_TRUE(in) << STATEPACK_PINNED_ARCHIVE;
  std::vector<uint8_t> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  Aligned aligned(bytes);
  auto decoded = decode(aligned.span());
  ASSERT_TRUE(decoded) << decoded.error().message;
  EXPECT_EQ(decoded->format_version, 3u);
  EXPECT_EQ(decoded->pipelines.size(), 7u);
  EXPECT_TRUE(encode(*decoded) == bytes) << "the writer no longer produces the pinned bytes";
}

// A depth bias reaches vkCreateGraphicsPipelines as it is: NaN and infinities are refused at load.
TEST(ArchiveFormat, NonFiniteDepthBiasIsCorrupt) {
  for (float bad : {std::nanf(""), INFINITY, -INFINITY}) {
    Fixture f;
    f.contents.pipelines[0].graphics.depth_bias_clamp = bad;
    auto bytes = encode(f.contents);
    Aligned aligned(bytes);
    auto decoded = decode(aligned.span());
    ASSERT_FALSE(decoded);
    EXPECT_NE(decoded.error().message.find("depth bias that is not a finite number"), std::string::npos)
        << decoded.error().message;
  }
}

TEST(ArchiveFormat, WrongMagicMisalignmentAndTrailingBytes) {
  Fixture f;
  auto bytes = encode(f.contents);
  {
    auto damaged = bytes;
    damaged[1] = 'X';
    Aligned aligned(damaged);
    auto decoded = decode(aligned.span());
    ASSERT_FALSE(decoded);
    EXPECT_EQ(decoded.error().code, ErrorCode::bad_magic);
  }
  {
    std::vector<uint8_t> shifted(bytes.size() + 1);
    std::memcpy(shifted.data() + 1, bytes.data(), bytes.size());
    Aligned aligned(shifted);
    auto decoded = decode(aligned.span().subspan(1));
    ASSERT_FALSE(decoded);
    EXPECT_EQ(decoded.error().code, ErrorCode::misaligned_memory);
  }
  {
    auto longer = bytes;
    longer.push_back(0);
    Aligned aligned(longer);
    auto decoded = decode(aligned.span());
    ASSERT_FALSE(decoded);
    EXPECT_EQ(decoded.error().code, ErrorCode::corrupt);
  }
}

}  // namespace
}  // namespace statepack::format
