// Hostile input: files that are not archives, archives edited and re-sealed with a correct checksum,
// and values beyond what the device allows. Each is an Error with a precise message, never a crash, an
// exception, a hang or a validation message.
#include <fcntl.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <fstream>

#include "common/forged_archive.hpp"
#include "common/vulkan_test_fixture.hpp"
#include "format/archive_file.hpp"
#include "format/spirv_walk.hpp"
#include "runtime/archive_access.hpp"
#include "support/file_io.hpp"

namespace statepack::testing {
namespace {

namespace fs = std::filesystem;

fs::path scratch_dir() {
  fs::path dir = fs::path(STATEPACK_TEST_OUTPUT_DIR) / "hostile";
  fs::create_directories(dir);
  return dir;
}

// The slice archive (kept alive: decoded SPIR-V spans point into it) and a copy of its contents.
struct Slice {
  Archive archive = Archive::from_file(STATEPACK_TEST_ARCHIVE).value();
  format::Contents contents = detail::ArchiveAccess::contents(archive);
  format::Pipeline& pipeline(std::string_view name) {
    return *std::find_if(contents.pipelines.begin(), contents.pipelines.end(),
                         [&](const format::Pipeline& p) { return p.name == name; });
  }
  // The contents with `count` copies of the compute pipeline in place of every pipeline, named
  // "P<first>", "P<first + 1>", ...
  format::Contents with_compute_copies(int count, int first) {
    format::Contents c = contents;
    format::Pipeline compute = pipeline("Fill Buffer PSO");
    c.pipelines.clear();
    for (int i = 0; i < count; ++i) {
      compute.name = "P" + std::to_string(first + i);
      c.pipelines.push_back(compute);
    }
    return c;
  }
};

// The contents of a corpus archive by name fragment, kept alive the same way.
struct Corpus {
  std::optional<Archive> archive;
  format::Contents contents;
  explicit Corpus(std::string_view fragment) {
    for (const auto& path : corpus_archives())
      if (path.find(fragment) != std::string::npos) archive.emplace(Archive::from_file(path).value());
    if (archive) contents = detail::ArchiveAccess::contents(*archive);
  }
};

Result<Archive> load(const format::Contents& contents, ForgedBytes& bytes) {
  bytes = ForgedBytes(format::encode(contents));
  return Archive::from_memory(bytes.span());
}

std::string load_error(const format::Contents& contents) {
  ForgedBytes bytes;
  auto archive = load(contents, bytes);
  return archive ? "loaded" : archive.error().message;
}

// --- files that are not regular files ---------------------------------------------------------------

TEST(HostileFiles, DirectoryIsRefusedWithItsPath) {
  const fs::path dir = scratch_dir() / "a_directory.spk";
  fs::create_directories(dir);
  auto archive = Archive::from_file(dir);
  ASSERT_FALSE(archive);
  EXPECT_EQ(archive.error().code, ErrorCode::io_error);
  EXPECT_EQ(archive.error().message, dir.string() + ": cannot read: it is a directory, not a regular file");
}

TEST(HostileFiles, FifoIsRefusedWithoutWaitingForAWriter) {
  const fs::path fifo = scratch_dir() / "a_fifo.spk";
  fs::remove(fifo);
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  const auto start = std::chrono::steady_clock::now();
  auto archive = Archive::from_file(fifo);  // without O_NONBLOCK this open would block forever
  ASSERT_FALSE(archive);
  EXPECT_EQ(archive.error().message, fifo.string() + ": cannot read: it is a FIFO, not a regular file");
  EXPECT_LT(std::chrono::steady_clock::now() - start, std::chrono::seconds(2));
  fs::remove(fifo);
}

TEST(HostileFiles, CharacterDeviceIsRefused) {
  auto archive = Archive::from_file("/dev/null");
  ASSERT_FALSE(archive);
  EXPECT_EQ(archive.error().message, "/dev/null: cannot read: it is a character device, not a regular file");
  auto zero = Archive::from_file("/dev/zero");  // endless: reading it whole would never finish
  ASSERT_FALSE(zero);
  EXPECT_EQ(zero.error().message, "/dev/zero: cannot read: it is a character device, not a regular file");
}

// Outputs report what went wrong as a code: a path that may not be an output is the caller's mistake
// (invalid_argument, which the CLI turns into its usage exit code), a failed write an io_error.
TEST(HostileFiles, OutputErrorsCarryTheirKindAsACode) {
  const fs::path dir = scratch_dir() / "output_kinds";
  fs::create_directories(dir / "a_directory");
  const std::vector<uint8_t> bytes = {1, 2, 3};
  auto onto_directory = detail::write_file_atomically(dir / "a_directory", bytes);
  ASSERT_FALSE(onto_directory);
  EXPECT_EQ(onto_directory.error().code, ErrorCode::invalid_argument) << onto_directory.error().message;
  EXPECT_NE(onto_directory.error().message.find("refusing to write"), std::string::npos);
  std::ofstream(dir / "input.json") << "{}";
  auto onto_input = detail::write_file_atomically(dir / "input.json", bytes, {dir / "input.json"});
  ASSERT_FALSE(onto_input);
  EXPECT_EQ(onto_input.error().code, ErrorCode::invalid_argument) << onto_input.error().message;
  auto nowhere = detail::write_file_atomically("/nonexistent/dir/out.spk", bytes);
  ASSERT_FALSE(nowhere);
  EXPECT_EQ(nowhere.error().code, ErrorCode::io_error) << nowhere.error().message;
  EXPECT_NE(nowhere.error().message.find("/nonexistent/dir/out.spk"), std::string::npos);
  ASSERT_TRUE(detail::write_file_atomically(dir / "fine.spk", bytes));
}

TEST(HostileFiles, MissingFileNamesTheOsReason) {
  auto archive = Archive::from_file("/nonexistent/dir/archive.spk");
  ASSERT_FALSE(archive);
  EXPECT_EQ(archive.error().message, "/nonexistent/dir/archive.spk: cannot open: No such file or directory");
}

// The message of loading `file` as an unprivileged user: as root, in a child process that gives up
// root first (root reads files whatever their permissions).
std::string unprivileged_load_error(const fs::path& file) {
  if (::geteuid() != 0) {
    auto archive = Archive::from_file(file);
    return archive ? "loaded" : archive.error().message;
  }
  int pipe_fds[2];
  if (::pipe(pipe_fds) != 0) return "pipe failed";
  const pid_t child = ::fork();
  if (child == 0) {
    ::close(pipe_fds[0]);
    std::string message = "setresuid failed";
    if (::setresgid(65534, 65534, 65534) == 0 && ::setresuid(65534, 65534, 65534) == 0) {
      auto archive = Archive::from_file(file);
      message = archive ? "loaded" : archive.error().message;
    }
    const ssize_t written = ::write(pipe_fds[1], message.data(), message.size());
    ::_exit(written == ssize_t(message.size()) ? 0 : 1);
  }
  ::close(pipe_fds[1]);
  std::string message;
  char buffer[512];
  for (ssize_t n; (n = ::read(pipe_fds[0], buffer, sizeof buffer)) > 0;) message.append(buffer, size_t(n));
  ::close(pipe_fds[0]);
  int status = 0;
  ::waitpid(child, &status, 0);
  return message;
}

TEST(HostileFiles, UnreadableFileNamesTheOsReason) {
  const fs::path file = scratch_dir() / "unreadable.spk";
  fs::copy_file(STATEPACK_TEST_ARCHIVE, file, fs::copy_options::overwrite_existing);
  fs::permissions(file, fs::perms::none);
  fs::permissions(scratch_dir(), fs::perms::all);  // the unprivileged child must reach the file
  const std::string message = unprivileged_load_error(file);
  fs::permissions(file, fs::perms::owner_all);
  EXPECT_EQ(message, file.string() + ": cannot open: Permission denied");
}

TEST(HostileFiles, EmptyFileIsTruncated) {
  const fs::path file = scratch_dir() / "empty.spk";
  std::ofstream(file).close();
  auto archive = Archive::from_file(file);
  ASSERT_FALSE(archive);
  EXPECT_EQ(archive.error().message,
            file.string() + ": truncated archive: 0 bytes is shorter than the 64-byte header");
}

// --- amplification -----------------------------------------------------------------------------------

// 2000 compute pipelines whose set layout lists all point at one 50,000-entry list: a 0.4 MB file
// that would decode into 400 MB of indices.
TEST(HostileArchive, SharedListsCannotAmplifyTheDecodedSize) {
  Slice slice;
  format::Contents c = slice.with_compute_copies(2000, 10000);
  c.pipelines[0].set_layouts.assign(50000, format::kNone);
  std::vector<uint8_t> bytes = format::encode(c);
  // Every PIPE record's set layout list {first, count} (bytes 20-27) now names the long one.
  for (const SectionEntry& s : sections_of(bytes)) {
    if (s.tag != tag_of("PIPE")) continue;
    const uint32_t first = get_u32(bytes, s.offset + 20), count = get_u32(bytes, s.offset + 24);
    ASSERT_EQ(count, 50000u);
    for (uint32_t r = 1; r < s.count; ++r) {
      put_u32(bytes, s.offset + 40 * r + 20, first);
      put_u32(bytes, s.offset + 40 * r + 24, count);
    }
  }
  reseal(bytes);
  ForgedBytes forged(bytes);
  const auto start = std::chrono::steady_clock::now();
  auto archive = Archive::from_memory(forged.span());
  const auto elapsed = std::chrono::steady_clock::now() - start;
  ASSERT_FALSE(archive);
  EXPECT_EQ(archive.error().code, ErrorCode::corrupt);
  const std::string budget = std::to_string(bytes.size() * 8 + (1 << 20));
  const std::string message = archive.error().message;
  EXPECT_EQ(message.rfind("archive in memory: corrupt archive: pipeline ", 0), 0u) << message;
  EXPECT_NE(message.find("' expands beyond the decoding budget of " + budget +
                         " bytes (8 x the file size + 1048576): records share lists or strings to amplify "
                         "the archive"),
            std::string::npos)
      << message;
  EXPECT_LT(elapsed, std::chrono::seconds(2));
}

// --- shader interfaces against stored layouts (at load, no Vulkan) ------------------------------------

// The shader checks' budget scales with the work the archive really asks for: 100,000 pipelines over
// one shader and one layout are one check, and load (they once failed with "expands beyond N steps").
TEST(HostileArchive, ManyPipelinesSharingAShaderAndLayoutLoad) {
  Slice slice;
  format::Contents c = slice.with_compute_copies(100000, 0);
  EXPECT_EQ(load_error(c), "loaded");
  // Still checked: the last one's layout without its set is found, by name.
  c.pipelines.back().set_layouts.clear();
  EXPECT_EQ(load_error(c),
            "archive in memory: corrupt archive: pipeline 'P99999': shader 'Fill Buffer CS' uses set 0, "
            "binding 0, which the pipeline's layout lacks");
}

// A set's check is made once per (SPIR-V blob, entry point, stage, set, layout), not per shader record:
// pipelines with shader records of their own over one blob and one layout cost one check, and one of
// them against another layout is still checked, and named.
TEST(HostileArchive, ShaderRecordsOfOneBlobAreCheckedPerLayout) {
  Slice slice;
  format::Contents c = slice.with_compute_copies(1000, 0);
  const format::Shader shader = c.shaders[c.pipelines[0].shaders[0]];
  for (auto& p : c.pipelines) {
    format::Shader own = shader;
    own.name = "CS of " + p.name;
    p.shaders = {uint32_t(c.shaders.size())};
    c.shaders.push_back(own);
  }
  EXPECT_EQ(load_error(c), "loaded");
  format::SetLayout hidden = c.set_layouts[c.pipelines[0].set_layouts[0]];
  hidden.bindings[0].stage_flags = VK_SHADER_STAGE_VERTEX_BIT;
  c.pipelines[700].set_layouts[0] = uint32_t(c.set_layouts.size());
  c.set_layouts.push_back(hidden);
  EXPECT_EQ(load_error(c),
            "archive in memory: corrupt archive: pipeline 'P700': binding 'Values' (set 0, binding 0) is not "
            "visible to the compute stage, which shader 'CS of P700' uses it from");
}

// From SPIR-V 1.4 on, an entry point's interface lists every global it uses, and two OpEntryPoints may
// name one function with different lists: each is checked by its own. Here "a" lists a storage buffer
// (set 0, binding 0) its function never touches, and "b" lists nothing, so a pipeline of "b" needs no
// set at all, even after a pipeline of "a" was checked against its layout.
TEST(HostileArchive, TwoEntryPointsOnOneFunctionAreCheckedByTheirOwnInterfaces) {
  std::vector<uint32_t> module{0x07230203u, 0x00010400u, 0, 64, 0};
  auto op = [&](uint32_t opcode, std::vector<uint32_t> operands) {
    module.push_back(uint32_t(operands.size() + 1) << 16 | opcode);
    module.insert(module.end(), operands.begin(), operands.end());
  };
  enum : uint32_t { kVoid = 1, kFunctionType, kMain, kLabel, kUint, kBlock, kPointer, kBuffer };
  const uint32_t name_a = 'a', name_b = 'b';  // one byte and its NUL: one word
  op(17, {1});                                // OpCapability Shader
  op(14, {0, 1});                             // OpMemoryModel Logical GLSL450
  op(15, {5, kMain, name_a, kBuffer});        // OpEntryPoint GLCompute %main "a" %buffer
  op(15, {5, kMain, name_b});                 // OpEntryPoint GLCompute %main "b"
  op(16, {kMain, 17, 1, 1, 1});               // LocalSize 1 1 1
  op(71, {kBuffer, 34, 0});                   // DescriptorSet 0
  op(71, {kBuffer, 33, 0});                   // Binding 0
  op(71, {kBlock, 2});                        // Block
  op(72, {kBlock, 0, 35, 0});                 // member 0 at offset 0
  op(19, {kVoid});
  op(33, {kFunctionType, kVoid});
  op(21, {kUint, 32, 0});
  op(30, {kBlock, kUint});
  op(32, {kPointer, 12, kBlock});  // StorageBuffer
  op(59, {kPointer, kBuffer, 12});
  op(54, {kVoid, kMain, 0, kFunctionType});
  op(248, {kLabel});
  op(253, {});  // OpReturn
  op(56, {});
  ASSERT_TRUE(spirv::walk(module)) << spirv::walk(module).error().message;

  Slice slice;
  format::Contents c = slice.with_compute_copies(2, 0);
  c.spirv.push_back(std::span<const uint32_t>(module));
  format::Shader a = c.shaders[c.pipelines[0].shaders[0]];
  a.blob = uint32_t(c.spirv.size() - 1);
  a.name = "A CS";
  a.entry_point = "a";
  format::Shader b = a;
  b.name = "B CS";
  b.entry_point = "b";
  c.pipelines[0].shaders = {uint32_t(c.shaders.size())};
  c.shaders.push_back(a);
  c.pipelines[1].shaders = {uint32_t(c.shaders.size())};
  c.shaders.push_back(b);
  c.pipelines[1].set_layouts.clear();
  EXPECT_EQ(load_error(c), "loaded");
  // And "a" still needs its set.
  c.pipelines[0].set_layouts.clear();
  EXPECT_EQ(
      load_error(c),
      "archive in memory: corrupt archive: pipeline 'P0': shader 'A CS' uses set 0, binding 0, which the "
      "pipeline's layout lacks");
}

TEST(HostileArchive, PipelineLayoutLackingASetTheShaderUses) {
  Slice slice;
  slice.pipeline("Fill Buffer PSO").set_layouts.clear();
  EXPECT_EQ(
      load_error(slice.contents),
      "archive in memory: corrupt archive: pipeline 'Fill Buffer PSO': shader 'Fill Buffer CS' uses set 0, "
      "binding 0, which the pipeline's layout lacks");
}

TEST(HostileArchive, BindingMissingFromItsSet) {
  Slice slice;
  auto& p = slice.pipeline("Fill Buffer PSO");
  slice.contents.set_layouts[p.set_layouts[0]].bindings[0].binding = 3;
  EXPECT_EQ(
      load_error(slice.contents),
      "archive in memory: corrupt archive: pipeline 'Fill Buffer PSO': shader 'Fill Buffer CS' uses set 0, "
      "binding 0, which the pipeline's layout lacks");
}

TEST(HostileArchive, IncompatibleDescriptorType) {
  Slice slice;
  auto& p = slice.pipeline("Fill Buffer PSO");
  slice.contents.set_layouts[p.set_layouts[0]].bindings[0].descriptor_type =
      VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER;
  EXPECT_EQ(
      load_error(slice.contents),
      "archive in memory: corrupt archive: pipeline 'Fill Buffer PSO': binding 'Values' (set 0, binding 0) "
      "is a uniform buffer descriptor, but shader 'Fill Buffer CS' declares a storage buffer or "
      "dynamic storage buffer");
}

TEST(HostileArchive, BindingInvisibleToTheShadersStage) {
  Slice slice;
  auto& p = slice.pipeline("Fill Buffer PSO");
  slice.contents.set_layouts[p.set_layouts[0]].bindings[0].stage_flags = VK_SHADER_STAGE_VERTEX_BIT;
  EXPECT_EQ(
      load_error(slice.contents),
      "archive in memory: corrupt archive: pipeline 'Fill Buffer PSO': binding 'Values' (set 0, binding 0) "
      "is not visible to the compute stage, which shader 'Fill Buffer CS' uses it from");
}

TEST(HostileArchive, TooFewDescriptorsForTheShadersArray) {
  Slice slice;
  auto& p = slice.pipeline("Fill Buffer PSO");
  slice.contents.set_layouts[p.set_layouts[0]].bindings[0].count = 0;
  EXPECT_EQ(
      load_error(slice.contents),
      "archive in memory: corrupt archive: pipeline 'Fill Buffer PSO': binding 'Values' (set 0, binding 0) "
      "holds 0 descriptor(s), but shader 'Fill Buffer CS' declares an array of 1");
}

TEST(HostileArchive, PushConstantsMissingOrTooSmall) {
  Slice slice;
  slice.pipeline("Fill Buffer PSO").push_constant_stages = VK_SHADER_STAGE_VERTEX_BIT;
  EXPECT_EQ(
      load_error(slice.contents),
      "archive in memory: corrupt archive: pipeline 'Fill Buffer PSO': shader 'Fill Buffer CS' uses push "
      "constants, which the pipeline's layout lacks for the compute stage");
  Slice small;
  small.pipeline("Fill Buffer PSO").push_constant_size = 8;
  EXPECT_EQ(load_error(small.contents),
            "archive in memory: corrupt archive: pipeline 'Fill Buffer PSO': push constants are 8 bytes, but "
            "shader 'Fill Buffer CS' uses 12");
}

TEST(HostileArchive, EntryPointAndStageMustExistInTheModule) {
  Slice renamed;
  for (auto& s : renamed.contents.shaders)
    if (s.name == "Fill Buffer CS") s.entry_point = "not_main";
  EXPECT_EQ(load_error(renamed.contents),
            "archive in memory: corrupt archive: shader 'Fill Buffer CS' has no compute entry point named "
            "'not_main' in its SPIR-V");
  Slice restaged;
  for (auto& s : restaged.contents.shaders)
    if (s.name == "Gradient PS") s.stage = VK_SHADER_STAGE_GEOMETRY_BIT;
  EXPECT_EQ(
      load_error(restaged.contents),
      "archive in memory: corrupt archive: shader 'Gradient PS' has no geometry entry point named 'main' in "
      "its SPIR-V");
}

TEST(HostileArchive, VertexInputWithoutAttribute) {
  Corpus corpus("input_layout");
  ASSERT_TRUE(corpus.archive);
  for (auto& p : corpus.contents.pipelines)
    if (p.name == "Instanced Mesh PSO")
      std::erase_if(p.graphics.vertex_attributes, [](auto& a) { return a.location == 0; });
  const std::string message = load_error(corpus.contents);
  EXPECT_EQ(
      message.rfind("archive in memory: corrupt archive: pipeline 'Instanced Mesh PSO': vertex shader '", 0),
      0u)
      << message;
  EXPECT_NE(message.find("' reads input location 0, which has no vertex attribute"), std::string::npos)
      << message;
}

// SPIR-V edited in place, its content hash and the file checksum recomputed.
std::string spirv_edit_error(size_t word, uint32_t value) {
  Slice slice;
  const uint32_t blob = [&] {
    for (const auto& s : slice.contents.shaders)
      if (s.name == "Fill Buffer CS") return s.blob;
    return 0u;
  }();
  std::vector<uint32_t> words(slice.contents.spirv[blob].begin(), slice.contents.spirv[blob].end());
  words.at(word) = value;
  slice.contents.spirv[blob] = words;
  return load_error(slice.contents);
}

TEST(HostileArchive, SpirvHeaderAndInstructionsAreWalkedWithBounds) {
  EXPECT_EQ(spirv_edit_error(1, 0x00020000),
            "archive in memory: corrupt archive: shader 'Fill Buffer CS': SPIR-V module has an unknown "
            "version word "
            "131072");
  EXPECT_EQ(
      spirv_edit_error(3, 0),
      "archive in memory: corrupt archive: shader 'Fill Buffer CS': SPIR-V module has an invalid id bound 0");
  EXPECT_EQ(
      spirv_edit_error(5, 0xFFFF0011),  // OpCapability claiming 65535 words
      "archive in memory: corrupt archive: shader 'Fill Buffer CS': SPIR-V word 5: instruction runs past the "
      "end of the module");
  EXPECT_EQ(
      spirv_edit_error(5, 0x00000011),
      "archive in memory: corrupt archive: shader 'Fill Buffer CS': SPIR-V word 5: instruction with a word "
      "count of zero");
}

TEST(HostileArchive, ShortenedSpirvIsRefused) {
  // Cutting the last instruction (OpFunctionEnd) keeps every word count valid: only the function
  // structure shows the cut, which the validation layer would otherwise crash on.
  Slice slice;
  const uint32_t blob = [&] {
    for (const auto& s : slice.contents.shaders)
      if (s.name == "Fill Buffer CS") return s.blob;
    return 0u;
  }();
  std::vector<uint32_t> words(slice.contents.spirv[blob].begin(), slice.contents.spirv[blob].end());
  ASSERT_EQ(words.back(), 0x00010038u);  // OpFunctionEnd
  words.pop_back();
  slice.contents.spirv[blob] = words;
  EXPECT_EQ(
      load_error(slice.contents),
      "archive in memory: corrupt archive: shader 'Fill Buffer CS': SPIR-V module ends inside a function");
}

// --- device limits (at unpack, before any vkCreate*) -----------------------------------------------

class HostileUnpack : public VulkanTest {
 protected:
  VkPhysicalDeviceLimits limits() {
    VkPhysicalDeviceProperties properties;
    vkGetPhysicalDeviceProperties(vk_->physical_device, &properties);
    return properties.limits;
  }
  // Loads edited contents and unpacks one pipeline; returns the error message.
  std::string unpack_error(const format::Contents& contents, const std::string& name) {
    ForgedBytes bytes;
    auto archive = load(contents, bytes);
    if (!archive) return "load: " + archive.error().message;
    auto dearchiver = Dearchiver::create(vk_->device_context());
    EXPECT_TRUE(dearchiver->add_archive(std::move(*archive)));
    for (const auto& p : contents.pipelines) {
      if (p.name != name) continue;
      auto pso = p.kind == format::PipelineKind::compute ? dearchiver->unpack_compute(name)
                                                         : dearchiver->unpack_graphics(name);
      return pso ? "unpacked" : pso.error().message;
    }
    return "no such pipeline";
  }
};

TEST_F(HostileUnpack, AbsurdPushConstantSizeIsRefusedQuickly) {
  Slice slice;
  slice.pipeline("Fill Buffer PSO").push_constant_size = 0x7FFFFFFC;
  const auto start = std::chrono::steady_clock::now();
  EXPECT_EQ(unpack_error(slice.contents, "Fill Buffer PSO"),
            "pipeline 'Fill Buffer PSO': the push constant size is 2147483644, beyond the device's "
            "maxPushConstantsSize of " +
                std::to_string(limits().maxPushConstantsSize));
  EXPECT_LT(std::chrono::steady_clock::now() - start, std::chrono::seconds(2));
}

TEST_F(HostileUnpack, DescriptorCountsBeyondTheDevice) {
  Slice slice;
  auto& p = slice.pipeline("Fill Buffer PSO");
  slice.contents.set_layouts[p.set_layouts[0]].bindings[0].count = 0xFFFFFFFF;
  EXPECT_EQ(unpack_error(slice.contents, "Fill Buffer PSO"),
            "pipeline 'Fill Buffer PSO': the descriptor count is 4294967295, beyond the device's "
            "maxDescriptorSetStorageBuffers of " +
                std::to_string(limits().maxDescriptorSetStorageBuffers));
}

// A stage's own limit, below the whole layout's: the message names the pipeline and the stage, words
// made only when a check fails.
TEST_F(HostileUnpack, DescriptorCountsBeyondOneStage) {
  const uint32_t per_stage = limits().maxPerStageDescriptorStorageBuffers;
  ASSERT_LT(per_stage, limits().maxDescriptorSetStorageBuffers);
  Slice slice;
  auto& p = slice.pipeline("Fill Buffer PSO");
  slice.contents.set_layouts[p.set_layouts[0]].bindings[0].count = per_stage + 1;
  EXPECT_EQ(unpack_error(slice.contents, "Fill Buffer PSO"),
            "pipeline 'Fill Buffer PSO' (compute stage): the descriptor count is " +
                std::to_string(per_stage + 1) +
                ", beyond the device's maxPerStageDescriptorStorageBuffers of " + std::to_string(per_stage));
}

TEST_F(HostileUnpack, MoreSetsThanTheDeviceBinds) {
  Slice slice;
  slice.pipeline("Fill Buffer PSO").set_layouts.resize(limits().maxBoundDescriptorSets + 1, format::kNone);
  EXPECT_EQ(unpack_error(slice.contents, "Fill Buffer PSO"),
            "pipeline 'Fill Buffer PSO': the descriptor set count is " +
                std::to_string(limits().maxBoundDescriptorSets + 1) +
                ", beyond the device's maxBoundDescriptorSets of " +
                std::to_string(limits().maxBoundDescriptorSets));
}

TEST_F(HostileUnpack, VertexInputBeyondTheDevice) {
  Corpus stride("input_layout");
  ASSERT_TRUE(stride.archive);
  for (auto& p : stride.contents.pipelines)
    if (p.name == "Instanced Mesh PSO") p.graphics.vertex_bindings[0].stride = 1 << 20;
  EXPECT_EQ(unpack_error(stride.contents, "Instanced Mesh PSO"),
            "pipeline 'Instanced Mesh PSO': the stride of vertex binding 0 is 1048576, beyond the device's "
            "maxVertexInputBindingStride of " +
                std::to_string(limits().maxVertexInputBindingStride));
  Corpus offset("input_layout");
  for (auto& p : offset.contents.pipelines)
    if (p.name == "Instanced Mesh PSO") p.graphics.vertex_attributes[0].offset = 1 << 20;
  EXPECT_NE(unpack_error(offset.contents, "Instanced Mesh PSO")
                .find("is 1048576, beyond the device's maxVertexInputAttributeOffset of " +
                      std::to_string(limits().maxVertexInputAttributeOffset)),
            std::string::npos);
  Corpus format("input_layout");
  for (auto& p : format.contents.pipelines)
    if (p.name == "Instanced Mesh PSO")
      p.graphics.vertex_attributes[0].format = VK_FORMAT_BC1_RGB_UNORM_BLOCK;
  EXPECT_NE(unpack_error(format.contents, "Instanced Mesh PSO")
                .find("has format VK_FORMAT_BC1_RGB_UNORM_BLOCK, which the device cannot read vertices from"),
            std::string::npos);
}

TEST_F(HostileUnpack, RenderTargetsBeyondTheDevice) {
  Slice samples;
  samples.pipeline("Gradient PSO").graphics.samples = 64;
  EXPECT_EQ(unpack_error(samples.contents, "Gradient PSO"),
            "pipeline 'Gradient PSO' renders with 64 samples, which the device does not support");
  Slice format;
  format.pipeline("Gradient PSO").graphics.color_formats[0] = VK_FORMAT_BC1_RGB_UNORM_BLOCK;
  EXPECT_EQ(unpack_error(format.contents, "Gradient PSO"),
            "pipeline 'Gradient PSO': render target 0 has format VK_FORMAT_BC1_RGB_UNORM_BLOCK, which the "
            "device cannot render to");
}

TEST_F(HostileUnpack, SignatureBeyondTheDevice) {
  Corpus corpus("signatures");
  ASSERT_TRUE(corpus.archive);
  for (auto& l : corpus.contents.set_layouts)
    if (l.name == "Frame Signature") l.bindings[0].count = 1u << 30;
  ForgedBytes bytes;
  auto archive = load(corpus.contents, bytes);
  ASSERT_TRUE(archive) << archive.error().message;
  auto dearchiver = Dearchiver::create(vk_->device_context());
  ASSERT_TRUE(dearchiver->add_archive(std::move(*archive)));
  auto sig = dearchiver->unpack_signature("Frame Signature");
  ASSERT_FALSE(sig);
  EXPECT_EQ(sig.error().message,
            "resource signature 'Frame Signature': the descriptor count is 1073741824, beyond "
            "the device's maxDescriptorSetUniformBuffers of " +
                std::to_string(limits().maxDescriptorSetUniformBuffers));
}

TEST_F(HostileUnpack, SparseBindingNumberIsRefused) {
  Slice slice;
  auto& p = slice.pipeline("Fill Buffer PSO");
  slice.contents.set_layouts[p.set_layouts[0]].bindings.push_back(
      {"Huge", 0x7FFFFFFC, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, 1, VK_SHADER_STAGE_COMPUTE_BIT, format::kNone});
  EXPECT_EQ(unpack_error(slice.contents, "Fill Buffer PSO"),
            "a set layout of pipeline 'Fill Buffer PSO': binding 'Huge' has the number 2147483644, beyond "
            "the 65535 "
            "this dearchiver accepts");
}

TEST_F(HostileUnpack, PipelineCacheFromADirectoryStartsEmpty) {
  const fs::path dir = scratch_dir() / "cache_directory";
  fs::create_directories(dir);
  auto cache = load_pipeline_cache({vk_->physical_device, vk_->device}, dir);
  ASSERT_TRUE(cache) << cache.error().message;
  EXPECT_FALSE(cache->reused);
  EXPECT_EQ(cache->reason, dir.string() + ": cannot read: it is a directory, not a regular file");
  vkDestroyPipelineCache(vk_->device, cache->cache, nullptr);
}

TEST_F(HostileUnpack, ModifyCallbackExceptionsBecomeErrors) {
  auto dearchiver = make_dearchiver();
  auto pso =
      dearchiver.unpack_graphics("Gradient PSO", [](PatchableState&) { throw std::runtime_error("boom"); });
  ASSERT_FALSE(pso);
  EXPECT_EQ(pso.error().code, ErrorCode::invalid_argument);
  EXPECT_EQ(pso.error().message, "pipeline 'Gradient PSO': the modify callback threw: boom");
}

}  // namespace
}  // namespace statepack::testing

namespace statepack::testing {
namespace {

// The OpenGL block is checked against its own SPIR-V before use, as the Vulkan part is at load: what
// reaches a GL driver has its entry point, no push constants, and every resource bound in its namespace.
// The check is format::check_opengl, which statepack_gl's add_archive and the packager's tools run;
// Archive (the Vulkan runtime) leaves the block it never reads alone.
Result<format::Contents> load_with_opengl(std::span<const uint8_t> bytes) {
  return format::load_archive_with_opengl(bytes, std::nullopt, "forged");
}

TEST(HostileArchive, OpenGlBlockIsCheckedAgainstItsSpirv) {
  auto loaded = format::load_archive_file(STATEPACK_GL_SLICE_ARCHIVE);
  ASSERT_TRUE(loaded) << loaded.error().message;
  const format::Contents& c = loaded->contents;
  ASSERT_EQ(c.gl_pipelines.size(), 2u);
  ASSERT_EQ(c.gl_pipelines[0].name, "Fill Buffer PSO");
  auto refused = [&](auto edit) -> std::string {
    format::Contents m = c;
    edit(m);
    ForgedBytes bytes(format::encode(m));
    auto checked = load_with_opengl(bytes.span());
    return checked ? "accepted" : checked.error().message;
  };
  EXPECT_EQ(refused([](format::Contents&) {}), "accepted");
  {  // The Vulkan runtime loads an archive whose OpenGL block is broken: it never reads that block.
    format::Contents m = c;
    m.gl_pipelines[0].shaders[0].blob = 999;
    ForgedBytes bytes(format::encode(m));
    EXPECT_TRUE(Archive::from_memory(bytes.span()));
    auto checked = load_with_opengl(bytes.span());
    ASSERT_FALSE(checked);
    EXPECT_NE(checked.error().message.find("refers to a missing SPIR-V blob"), std::string::npos)
        << checked.error().message;
  }
  auto expect = [](const std::string& message, const char* part) {
    EXPECT_NE(message.find(part), std::string::npos) << "expected '" << part << "' in: " << message;
  };
  // Values (the storage buffer) left out of the table.
  expect(refused([](format::Contents& m) {
           auto& b = m.gl_pipelines[0].bindings;
           b.erase(std::remove_if(b.begin(), b.end(),
                                  [](const format::GlBinding& x) { return x.name == "Values"; }),
                   b.end());
         }),
         "OpenGL pipeline 'Fill Buffer PSO', shader 'Fill Buffer CS': the resource at binding 0 has no "
         "binding of "
         "its kind");
  // Bound for another stage only.
  expect(refused([](format::Contents& m) {
           for (auto& b : m.gl_pipelines[0].bindings) b.stages = 0x1;
         }),
         "has an invalid kind, count or stages");
  // An entry point the module lacks.
  expect(refused([](format::Contents& m) { m.gl_pipelines[0].shaders[0].entry_point = "other"; }),
         "has no compute entry point named 'other'");
  // The Vulkan compilation (push constants) handed to OpenGL.
  expect(refused([](format::Contents& m) {
           m.gl_pipelines[0].shaders[0].blob = m.shaders[0].blob;
           for (const auto& s : m.shaders)
             if (s.stage == 0x20) m.gl_pipelines[0].shaders[0].blob = s.blob;
         }),
         "uses push constants, which OpenGL does not have");
  // A header that names no OpenGL backend.
  expect(refused([](format::Contents& m) { m.backends = format::kBackendVulkan; }),
         "names no OpenGL backend");
  // A module with a separate texture and sampler (HLSL's Texture2D + SamplerState, compiled for Vulkan)
  // in an OpenGL slot, even with texture bindings for both names: OpenGL has no separate samplers.
  Corpus hlsl("hlsl_entry_points");
  ASSERT_TRUE(hlsl.archive);
  const format::Shader* quad = nullptr;
  for (const auto& shader : hlsl.contents.shaders)
    if (shader.name == "Quad PS") quad = &shader;
  ASSERT_NE(quad, nullptr);
  expect(refused([&](format::Contents& m) {
           m.spirv.push_back(hlsl.contents.spirv[quad->blob]);
           for (auto& p : m.gl_pipelines)
             if (p.name == "Gradient PSO") {
               for (auto& shader : p.shaders)
                 if (shader.stage == 0x10)
                   shader = {"Quad PS", 0x10, uint32_t(m.spirv.size() - 1), quad->entry_point};
               p.bindings = {{"g_Texture", 2, 0, 1, 0x10}, {"g_Texture_sampler", 2, 1, 1, 0x10}};
             }
         }),
         "OpenGL pipeline 'Gradient PSO', shader 'Quad PS': the resource at binding 0 is of a kind OpenGL "
         "cannot bind");
}

// Only capabilities OpenGL 4.5 with GL_ARB_gl_spirv defines reach the GL driver: Mesa's llvmpipe crashes
// linking a fragment-barycentric module (found with a public shader collection).
TEST(HostileArchive, OpenGlModulesWithCapabilitiesOutsideOpenGlAreRefused) {
  auto loaded = format::load_archive_file(STATEPACK_GL_SLICE_ARCHIVE);
  ASSERT_TRUE(loaded) << loaded.error().message;
  const format::Contents& c = loaded->contents;
  const uint32_t blob = c.gl_pipelines.at(0).shaders.at(0).blob;
  for (uint32_t capability :
       {5284u /* FragmentBarycentricKHR */, 4439u /* MultiView */, 40u /* InputAttachment */}) {
    std::vector<uint32_t> words(c.spirv[blob].begin(), c.spirv[blob].end());
    words.insert(words.begin() + 5, {(2u << 16) | 17u, capability});  // OpCapability, first instruction
    format::Contents m = c;
    m.spirv[blob] = words;
    ForgedBytes bytes(format::encode(m));
    auto archive = load_with_opengl(bytes.span());
    ASSERT_FALSE(archive) << capability;
    EXPECT_NE(archive.error().message.find("declares SPIR-V capability " + std::to_string(capability) +
                                           ", which OpenGL 4.5 with GL_ARB_gl_spirv does not have"),
              std::string::npos)
        << archive.error().message;
  }
}

}  // namespace
}  // namespace statepack::testing
