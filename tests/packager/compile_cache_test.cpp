// statepack pack --cache-dir: a hit for an unchanged shader, a miss for any change of what decides its
// SPIR-V (its text, an #include's text, where an #include is found, macros, options), damaged entries
// ignored and rewritten, two packs sharing the cache at once, the size bound. The archive is always the
// bytes a pack without a cache writes.
#include <gtest/gtest.h>
#include <sys/stat.h>

#include <algorithm>
#include <chrono>

#include <filesystem>
#include <fstream>
#include <functional>
#include <regex>
#include <string>
#include <thread>

#include "common/run_command.hpp"
#include "common/text_files.hpp"

namespace {

namespace fs = std::filesystem;
using statepack::testing::CommandResult;
using statepack::testing::run_command;

using statepack::testing::read_file;
using statepack::testing::write_file;

struct CacheStats {
  int hits = -1, misses = -1, damaged = -1, written = -1, removed = -1;
};

class CompileCacheTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = statepack::testing::fresh_test_dir(STATEPACK_TEST_OUTPUT_DIR, "compile_cache");
    // Two compute shaders sharing an #include (one of them including a second one from an -s
    // directory), and an inline HLSL shader.
    write_file(dir_ / "project.json", R"({"Pipelines": [
      {"PSODesc": {"Name": "A"}, "pCS": {"Desc": {"Name": "A CS"}, "FilePath": "a.comp",
                                         "Macros": [{"Name": "SCALE", "Definition": "2u"}]}},
      {"PSODesc": {"Name": "B"}, "pCS": {"Desc": {"Name": "B CS"}, "FilePath": "b.comp"}},
      {"PSODesc": {"Name": "H"}, "pCS": {"Desc": {"Name": "H CS"}, "SourceLanguage": "HLSL",
        "Source": "RWStructuredBuffer<uint> data;\n[numthreads(4, 1, 1)] void main(uint3 id : SV_DispatchThreadID) { data[id.x] = id.x; }\n"}}]})");
    write_file(dir_ / "common.glsl", "uint twice(uint x) { return 2u * x; }\n");
    write_file(dir_ / "a.comp",
               "#version 450\n#extension GL_GOOGLE_include_directive : require\n#include \"common.glsl\"\n"
               "layout(local_size_x = 64) in;\nlayout(set = 0, binding = 0) buffer Data { uint v[]; } data;\n"
               "void main() { data.v[gl_GlobalInvocationID.x] = twice(gl_GlobalInvocationID.x) * SCALE; }\n");
    write_file(dir_ / "b.comp",
               "#version 450\n#extension GL_GOOGLE_include_directive : require\n#include \"common.glsl\"\n"
               "#include \"helper.glsl\"\nlayout(local_size_x = 32) in;\n"
               "layout(set = 0, binding = 0) buffer Data { uint v[]; } data;\n"
               "void main() { data.v[gl_GlobalInvocationID.x] = helper(twice(gl_GlobalInvocationID.x)); }\n");
    write_file(dir_ / "inc" / "helper.glsl", "uint helper(uint x) { return x + 1u; }\n");
    fs::create_directories(dir_ / "early");  // an -s directory searched before inc/
  }

  // Packs with the cache (or without: `cache` false) into `out`; the stats from --time-report. The
  // shaders' entries are what these tests check: the archive record (archive_reuse.hpp) is off unless
  // `reuse` (a pack that reuses the archive looks nothing up).
  CacheStats pack(const std::string& out, const std::string& extra = "", bool cache = true,
                  bool reuse = false) {
    CommandResult run = run_command("cd '" + dir_.string() +
                                    "' && '" STATEPACK_EXE "' pack -i project.json -s early -s inc -o '" +
                                    out + "' --vulkan --time-report " + (cache ? "--cache-dir cache " : "") +
                                    (reuse ? "" : "--no-archive-reuse ") + extra);
    EXPECT_EQ(run.exit_code, 0) << run.output;
    last_output_ = run.output;
    CacheStats s;
    static const std::regex line(
        R"(cache: (\d+) hits, (\d+) misses, (\d+) damaged, (\d+) written, (\d+) removed)");
    std::smatch m;
    if (std::regex_search(run.output, m, line))
      s = {std::stoi(m[1]), std::stoi(m[2]), std::stoi(m[3]), std::stoi(m[4]), std::stoi(m[5])};
    return s;
  }
  // The archive a pack without a cache writes for the same inputs.
  std::string clean_bytes(const std::string& extra = "") {
    pack("clean.spk", extra, false);
    return read_file(dir_ / "clean.spk");
  }
  // The entry files: the shaders' (compiles and finalisations) and the pack's bundle, which holds all of
  // them and so is the largest.
  std::vector<fs::path> all_entries() const {
    std::vector<fs::path> out;
    for (const auto& e : fs::recursive_directory_iterator(dir_ / "cache" / "v2"))
      if (e.is_regular_file() && e.path().filename().string().size() == 64) out.push_back(e.path());
    std::sort(out.begin(), out.end(),
              [](const fs::path& a, const fs::path& b) { return fs::file_size(a) < fs::file_size(b); });
    return out;
  }
  std::vector<fs::path> entries() const {
    std::vector<fs::path> out = all_entries();
    if (!out.empty()) out.pop_back();
    return out;
  }
  fs::path bundle() const { return all_entries().back(); }
  // The entry that holds `archive` (the project's archive record), or an empty path.
  fs::path entry_holding(const std::string& archive) const {
    for (const fs::path& entry : all_entries())
      if (read_file(entry).find(archive) != std::string::npos) return entry;
    return {};
  }
  // An output that is one of the inputs (a hard link to `shader`) is refused as a pack refuses it, and
  // the shader is left as it was.
  void expect_an_output_linked_to_refused(const std::string& shader) {
    fs::create_hard_link(dir_ / shader, dir_ / "linked.spk");
    const std::string text = read_file(dir_ / shader);
    const CommandResult refused =
        run_command("cd '" + dir_.string() +
                    "' && '" STATEPACK_EXE
                    "' pack -i project.json -s early -s inc -o linked.spk --vulkan --cache-dir cache");
    EXPECT_NE(refused.exit_code, 0) << refused.output;
    EXPECT_NE(refused.output.find("never replaces its inputs"), std::string::npos) << refused.output;
    EXPECT_EQ(read_file(dir_ / shader), text);
  }
  static ino_t inode(const fs::path& path) {
    struct stat st {};
    return ::stat(path.c_str(), &st) == 0 ? st.st_ino : 0;
  }

  fs::path dir_;
  std::string last_output_;
};

// 3 compiles + 3 finalisations.
constexpr int kEntries = 6;

TEST_F(CompileCacheTest, AnUnchangedProjectIsNotCompiledAgainAndTheBytesAreTheSame) {
  CacheStats cold = pack("cold.spk");
  EXPECT_EQ(cold.hits, 0);
  EXPECT_EQ(cold.misses, kEntries);
  EXPECT_EQ(cold.written, kEntries);
  EXPECT_EQ(all_entries().size(), size_t(kEntries + 1));  // and the pack's bundle
  EXPECT_TRUE(fs::exists(dir_ / "cache" / "CACHEDIR.TAG"));
  const ino_t bundle_written = inode(bundle());
  CacheStats warm = pack("warm.spk");
  EXPECT_EQ(warm.hits, kEntries) << last_output_;
  EXPECT_EQ(warm.misses, 0);
  EXPECT_EQ(warm.written, 0);
  // Every entry came from the bundle, which the warm pack did not need to write again.
  EXPECT_NE(last_output_.find(std::to_string(kEntries) + " entries read from the pack's bundle"),
            std::string::npos)
      << last_output_;
  EXPECT_EQ(all_entries().size(), size_t(kEntries + 1));
  EXPECT_EQ(inode(bundle()), bundle_written);  // (a rewrite renames a new file into place)
  const std::string clean = clean_bytes();
  EXPECT_EQ(read_file(dir_ / "cold.spk"), clean);
  EXPECT_EQ(read_file(dir_ / "warm.spk"), clean);
  // The depfile lists the #includes also when nothing was compiled.
  pack("warm.spk", "--depfile warm.d");
  const std::string depfile = read_file(dir_ / "warm.d");
  for (const char* file : {"a.comp", "b.comp", "common.glsl", "helper.glsl", "project.json"})
    EXPECT_NE(depfile.find(file), std::string::npos) << file << " missing from\n" << depfile;
}

// Each change misses exactly where it should, and the archive is the one a clean pack makes.
TEST_F(CompileCacheTest, AnyChangeToWhatDecidesTheSpirvMisses) {
  pack("first.spk");
  struct Change {
    const char* what;
    std::function<void()> apply;
    std::string extra;
    int compile_misses;  // of the 3 compiles (finalisations miss when the module changed)
  };
  const fs::path root = dir_;
  const Change changes[] = {
      {"a shared #include's text",
       [&] { write_file(root / "common.glsl", "uint twice(uint x) { return x + x; }\n"); }, "", 2},
      {"an #include found earlier in the -s directories",
       [&] { write_file(root / "early" / "helper.glsl", "uint helper(uint x) { return x + 2u; }\n"); }, "",
       1},
      {"a shader's own text",
       [&] { write_file(root / "a.comp", read_file(root / "a.comp") + "// edited\n"); }, "", 1},
      {"a notation macro",
       [&] {
         std::string json = read_file(root / "project.json");
         json.replace(json.find("\"2u\""), 4, "\"3u\"");
         write_file(root / "project.json", json);
       },
       "", 1},
      {"a -D macro", [] {}, "-D UNUSED_BY_ALL=1", 3},
      {"the Vulkan version", [] {}, "-D UNUSED_BY_ALL=1 --vulkan_version 1.1", 3},
  };
  std::string extra;
  for (const Change& c : changes) {
    SCOPED_TRACE(c.what);
    c.apply();
    extra = c.extra;
    const CacheStats s = pack("changed.spk", extra);
    // Compile misses are the misses beyond the finalisations of modules that changed.
    EXPECT_GE(s.misses, c.compile_misses) << last_output_;
    EXPECT_LE(s.misses, 2 * c.compile_misses) << last_output_;
    EXPECT_EQ(read_file(dir_ / "changed.spk"), clean_bytes(extra));
    const CacheStats again = pack("again.spk", extra);
    EXPECT_EQ(again.misses, 0) << last_output_;
    EXPECT_EQ(read_file(dir_ / "again.spk"), read_file(dir_ / "changed.spk"));
  }
  // Optimisation: the compiles still hit; only the finalisations miss.
  const CacheStats optimized = pack("optimized.spk", extra + " --optimize size");
  EXPECT_EQ(optimized.misses, 3) << last_output_;
  EXPECT_EQ(read_file(dir_ / "optimized.spk"), clean_bytes(extra + " --optimize size"));
}

// Truncated, damaged, foreign and linked entries are misses, written again; the archive is unchanged.
TEST_F(CompileCacheTest, DamagedEntriesAreIgnoredAndRewritten) {
  pack("first.spk");
  const std::string clean = clean_bytes();
  auto all = entries();
  ASSERT_EQ(all.size(), size_t(kEntries));
  fs::resize_file(all[0], fs::file_size(all[0]) / 2);  // truncated
  {
    std::string bytes = read_file(all[1]);
    bytes[bytes.size() - 3] ^= 0x40;  // one bit of the payload
    write_file(all[1], bytes);
  }
  write_file(all[2], "not an entry at all");
  fs::remove(all[3]);
  fs::create_symlink(dir_ / "project.json", all[3]);  // a planted link: never read through, replaced
  fs::remove(bundle());                               // else the entries come from it
  const CacheStats s = pack("damaged.spk");
  EXPECT_EQ(s.damaged, 4) << last_output_;  // the link too
  EXPECT_EQ(s.misses, 4) << last_output_;
  EXPECT_EQ(read_file(dir_ / "damaged.spk"), clean);
  EXPECT_FALSE(fs::is_symlink(all[3]));
  EXPECT_NE(read_file(dir_ / "project.json").find("Pipelines"), std::string::npos);  // the target untouched
  const CacheStats healed = pack("healed.spk");
  EXPECT_EQ(healed.hits, kEntries) << last_output_;
  EXPECT_EQ(read_file(dir_ / "healed.spk"), clean);
}

// A bundle damaged, planted, stale or another project's costs only its read: the entries come from their
// own files, the archive is the same, and the next pack writes a whole bundle again.
TEST_F(CompileCacheTest, ABundleThatCannotServeIsReadAroundAndWrittenAgain) {
  pack("first.spk");
  const std::string clean = clean_bytes();
  const fs::path bundle_path = bundle();
  const std::string whole = read_file(bundle_path);
  std::string flipped = whole;
  flipped[flipped.size() - 3] ^= 0x40;  // one bit of its payload
  const std::string damages[] = {whole.substr(0, whole.size() / 2), flipped, "not a bundle"};
  for (const std::string& damaged : damages) {
    write_file(bundle_path, damaged);
    const CacheStats s = pack("damaged.spk");
    EXPECT_EQ(s.hits, kEntries) << last_output_;
    EXPECT_EQ(s.damaged, 1) << last_output_;
    EXPECT_NE(last_output_.find(" 0 entries read from the pack's bundle"), std::string::npos) << last_output_;
    EXPECT_EQ(read_file(dir_ / "damaged.spk"), clean);
    EXPECT_EQ(read_file(bundle_path), whole);  // written again, the same
  }
  // A link planted in its place is not read through, and is replaced.
  fs::remove(bundle_path);
  fs::create_symlink(dir_ / "project.json", bundle_path);
  EXPECT_EQ(pack("linked.spk").hits, kEntries) << last_output_;
  EXPECT_FALSE(fs::is_symlink(bundle_path));
  EXPECT_EQ(read_file(bundle_path), whole);
  EXPECT_NE(read_file(dir_ / "project.json").find("Pipelines"), std::string::npos);
  // Stale: a shader changed since; its entries miss (the bundle's compile lists the old text's hash),
  // the others come from the bundle, and the new bundle holds the new compile.
  write_file(dir_ / "a.comp", read_file(dir_ / "a.comp") + "// edited\n");
  const CacheStats stale = pack("stale.spk");
  EXPECT_EQ(stale.misses, 1) << last_output_;  // A's compile (a comment: its finalisation is the same)
  EXPECT_EQ(read_file(dir_ / "stale.spk"), clean_bytes());
  EXPECT_EQ(pack("again.spk").hits, kEntries) << last_output_;
  EXPECT_NE(last_output_.find(std::to_string(kEntries) + " entries read from the pack's bundle"),
            std::string::npos)
      << last_output_;
  // An include changed under an unchanged shader keeps the compile's key: the bundle serves the old
  // compile once (a miss, its include's hash differs), then the rewritten one.
  write_file(dir_ / "common.glsl", "uint twice(uint x) { return x << 1u; }\n");
  EXPECT_EQ(pack("include.spk").hits, 2) << last_output_;  // H
  EXPECT_EQ(pack("include_again.spk").hits, kEntries) << last_output_;
  EXPECT_NE(last_output_.find(std::to_string(kEntries) + " entries read from the pack's bundle"),
            std::string::npos)
      << last_output_;
  EXPECT_EQ(read_file(dir_ / "include_again.spk"), clean_bytes());
  // The same with an include change that leaves every module as it was (a comment): the compiles are
  // rewritten under their old names, the finalisations hit, and the bundle must still take the new
  // compiles (else every later pack would miss them again).
  write_file(dir_ / "common.glsl", read_file(dir_ / "common.glsl") + "// a comment\n");
  EXPECT_EQ(pack("comment.spk").misses, 2) << last_output_;  // A's and B's compiles
  EXPECT_EQ(pack("comment_again.spk").hits, kEntries) << last_output_;
  EXPECT_NE(last_output_.find(std::to_string(kEntries) + " entries read from the pack's bundle"),
            std::string::npos)
      << last_output_;
  // Another set of options has its own bundle: its first pack reads the entries it shares from files.
  EXPECT_EQ(pack("optimized.spk", "--optimize size").hits, 3) << last_output_;  // the compiles
  EXPECT_NE(last_output_.find(" 0 entries read from the pack's bundle"), std::string::npos) << last_output_;
  EXPECT_EQ(pack("optimized.spk", "--optimize size").hits, kEntries) << last_output_;
  EXPECT_NE(last_output_.find(std::to_string(kEntries) + " entries read from the pack's bundle"),
            std::string::npos)
      << last_output_;
  EXPECT_EQ(pack("again.spk").hits, kEntries) << last_output_;  // the first set's bundle is still whole
  EXPECT_NE(last_output_.find(std::to_string(kEntries) + " entries read from the pack's bundle"),
            std::string::npos)
      << last_output_;
}

// One changed shader of many leaves the bundle as it is: its two new entries are read from their own
// files until those beside the bundle and those it holds unused pass 1/32 of the entries used; then it is
// written again, holding them. Every archive is the one a clean pack makes.
TEST_F(CompileCacheTest, ABundleIsWrittenAgainOnlyWhenWhatItLacksCounts) {
  constexpr int kShaders = 64;  // 128 entries: 4 beside or unused are within 1/32, 8 are not
  std::string json = R"({"Pipelines": [)";
  auto write_shader = [&](int i, int constant) {
    write_file(dir_ / ("many_" + std::to_string(i) + ".comp"),
               "#version 450\nlayout(local_size_x = 1) in;\n"
               "layout(std430, binding = 0) buffer B { uint v[]; };\n"
               "void main() { v[0] = " +
                   std::to_string(constant) + "u; }\n");
  };
  for (int i = 0; i < kShaders; ++i) {
    write_shader(i, i);
    json += std::string(i ? "," : "") + R"({"PSODesc": {"Name": "P)" + std::to_string(i) +
            R"("}, "pCS": {"Desc": {"Name": "S)" + std::to_string(i) + R"("}, "FilePath": "many_)" +
            std::to_string(i) + R"(.comp"}})";
  }
  write_file(dir_ / "project.json", json + "]}");
  const std::string from_bundle = " entries read from the pack's bundle";
  EXPECT_EQ(pack("cold.spk").written, 2 * kShaders) << last_output_;
  const ino_t first = inode(bundle());
  // One shader changed: its compile and finalisation are new, the bundle is not written again.
  write_shader(0, 1000);
  EXPECT_EQ(pack("one.spk").misses, 2) << last_output_;
  EXPECT_EQ(read_file(dir_ / "one.spk"), clean_bytes());
  EXPECT_EQ(inode(bundle()), first);
  // The next pack finds the two new entries in their own files, the rest in the bundle.
  const CacheStats again = pack("again.spk");
  EXPECT_EQ(again.hits, 2 * kShaders) << last_output_;
  EXPECT_NE(last_output_.find(std::to_string(2 * kShaders - 2) + from_bundle), std::string::npos)
      << last_output_;
  EXPECT_EQ(read_file(dir_ / "again.spk"), read_file(dir_ / "one.spk"));
  EXPECT_EQ(inode(bundle()), first);
  // A second shader changed: 4 beside the bundle and 4 in it unused, past 128 / 32; written again.
  write_shader(1, 1001);
  EXPECT_EQ(pack("two.spk").misses, 2) << last_output_;
  EXPECT_EQ(read_file(dir_ / "two.spk"), clean_bytes());
  EXPECT_NE(inode(bundle()), first);
  EXPECT_EQ(pack("whole.spk").hits, 2 * kShaders) << last_output_;
  EXPECT_NE(last_output_.find(std::to_string(2 * kShaders) + from_bundle), std::string::npos) << last_output_;
  EXPECT_EQ(read_file(dir_ / "whole.spk"), read_file(dir_ / "two.spk"));
}

// Two packs at once on one new cache: both succeed with the same bytes, and the cache they leave is whole.
TEST_F(CompileCacheTest, TwoPacksShareTheCacheAtOnce) {
  const std::string clean = clean_bytes();
  CommandResult runs[2];
  std::thread other([&] {
    runs[1] = run_command("cd '" + dir_.string() +
                          "' && '" STATEPACK_EXE
                          "' pack -i project.json -s early -s inc -o two.spk --vulkan --cache-dir cache");
  });
  runs[0] = run_command("cd '" + dir_.string() +
                        "' && '" STATEPACK_EXE
                        "' pack -i project.json -s early -s inc -o one.spk --vulkan --cache-dir cache");
  other.join();
  EXPECT_EQ(runs[0].exit_code, 0) << runs[0].output;
  EXPECT_EQ(runs[1].exit_code, 0) << runs[1].output;
  EXPECT_EQ(read_file(dir_ / "one.spk"), clean);
  EXPECT_EQ(read_file(dir_ / "two.spk"), clean);
  const CacheStats after = pack("after.spk");
  EXPECT_EQ(after.hits, kEntries) << last_output_;
  EXPECT_EQ(after.damaged, 0);
  for (const auto& e : fs::recursive_directory_iterator(dir_ / "cache" / "v2"))
    EXPECT_FALSE(e.path().filename().string().starts_with(".tmp-")) << e.path();
}

// The size bound trims the entries a pack neither wrote nor read, least recently used first; `statepack
// cache prune` trims on demand; a subdirectory replaced by a link is not written through.
TEST_F(CompileCacheTest, TheCacheStaysWithinItsBound) {
  pack("first.spk");
  ASSERT_EQ(all_entries().size(), size_t(kEntries + 1));
  // A bound nothing fits in: the next pack that writes removes every entry it neither wrote nor read.
  write_file(dir_ / "common.glsl", "uint twice(uint x) { return x << 1u; }\n");  // A and B change, H not
  const CacheStats small = pack("small.spk", "--cache-max-size 1");
  EXPECT_EQ(small.hits, 2) << last_output_;  // H's compile and finalisation
  // A's and B's compiles (rewritten in place: an entry's name leaves the #includes out) and their new
  // finalisations; the old finalisations are removed.
  EXPECT_EQ(small.written, 4) << last_output_;
  EXPECT_EQ(small.removed, 2) << last_output_;
  EXPECT_EQ(all_entries().size(), size_t(kEntries + 1));  // the bundle, rewritten, stays too
  // Nothing written: nothing trimmed, every entry a hit.
  EXPECT_EQ(pack("again.spk", "--cache-max-size 1").hits, kEntries) << last_output_;
  CommandResult prune =
      run_command("'" STATEPACK_EXE "' cache prune '" + (dir_ / "cache").string() + "' --max-size 0");
  EXPECT_EQ(prune.exit_code, 0) << prune.output;
  EXPECT_NE(prune.output.find(": 7 entries, "), std::string::npos) << prune.output;  // 6 and the bundle
  EXPECT_NE(prune.output.find("-> 0 entries, 0 bytes"), std::string::npos) << prune.output;
  EXPECT_TRUE(all_entries().empty());
  CommandResult not_a_cache = run_command("'" STATEPACK_EXE "' cache prune '" + dir_.string() + "/inc'");
  EXPECT_EQ(not_a_cache.exit_code, 2) << not_a_cache.output;
  EXPECT_NE(not_a_cache.output.find("is not a statepack cache directory"), std::string::npos)
      << not_a_cache.output;

  // Every entry's subdirectory replaced by a link to a directory of its own: nothing is written there.
  fs::remove_all(dir_ / "cache" / "v2");
  fs::create_directories(dir_ / "cache" / "v2");
  fs::create_directories(dir_ / "elsewhere");
  for (int i = 0; i < 256; ++i) {
    char name[3];
    std::snprintf(name, sizeof name, "%02x", i);
    fs::create_directory_symlink(dir_ / "elsewhere", dir_ / "cache" / "v2" / name);
  }
  CommandResult linked =
      run_command("cd '" + dir_.string() +
                  "' && '" STATEPACK_EXE
                  "' pack -i project.json -s early -s inc -o linked.spk --vulkan --cache-dir cache");
  EXPECT_EQ(linked.exit_code, 0) << linked.output;
  EXPECT_NE(linked.output.find("statepack: warning: --cache-dir: "), std::string::npos) << linked.output;
  EXPECT_TRUE(fs::is_empty(dir_ / "elsewhere"));
  EXPECT_EQ(read_file(dir_ / "linked.spk"), clean_bytes());
}

}  // namespace

// --- the archive record (archive_reuse.hpp): a repack that changed nothing writes the recorded bytes ---

constexpr const char* kReused = "nothing changed since the pack that recorded this archive";

TEST_F(CompileCacheTest, AnUnchangedPackWritesTheRecordedArchive) {
  const CacheStats cold = pack("cold.spk", "--depfile cold.d", true, true);
  EXPECT_EQ(cold.misses, kEntries) << last_output_;
  EXPECT_EQ(last_output_.find(kReused), std::string::npos) << last_output_;
  fs::remove(dir_ / "cold.spk");  // the record is the cache's own copy, not the output
  const CacheStats warm = pack("warm.spk", "--depfile warm.d", true, true);
  EXPECT_NE(last_output_.find(kReused), std::string::npos) << last_output_;
  EXPECT_EQ(warm.hits, -1) << "nothing was looked up\n" << last_output_;
  EXPECT_EQ(read_file(dir_ / "warm.spk"), clean_bytes());
  // The depfile is the one a pack writes: every file read, #includes too.
  std::string expected = read_file(dir_ / "cold.d");
  expected.replace(expected.find("cold.spk"), 8, "warm.spk");
  EXPECT_EQ(read_file(dir_ / "warm.d"), expected);
  // --print_contents reads the written archive back as a pack does (the record keeps it aligned).
  const CommandResult printed = run_command(
      "cd '" + dir_.string() +
      "' && '" STATEPACK_EXE
      "' pack -i project.json -s early -s inc -o printed.spk --vulkan --cache-dir cache --time-report "
      "--print_contents");
  EXPECT_EQ(printed.exit_code, 0) << printed.output;
  EXPECT_NE(printed.output.find(kReused), std::string::npos) << printed.output;
  EXPECT_NE(printed.output.find("pipeline 'A'"), std::string::npos) << printed.output;
  // --no-archive-reuse makes it again, from the shaders' entries.
  const CacheStats again = pack("again.spk");
  EXPECT_EQ(again.hits, kEntries) << last_output_;
  EXPECT_EQ(read_file(dir_ / "again.spk"), clean_bytes());
  expect_an_output_linked_to_refused("a.comp");
}

// Every change of what decides the archive misses the record (and the pack records the new archive);
// each archive is the one a clean pack makes.
TEST_F(CompileCacheTest, AnyChangeMissesTheArchiveRecord) {
  pack("first.spk", "", true, true);
  const fs::path root = dir_;
  auto edit_notation = [&](const std::string& from, const std::string& to) {
    std::string json = read_file(root / "project.json");
    json.replace(json.find(from), from.size(), to);
    write_file(root / "project.json", json);
  };
  const std::pair<const char*, std::function<void()>> changes[] = {
      {"a shared #include's text",
       [&] { write_file(root / "common.glsl", "uint twice(uint x) { return x + x; }\n"); }},
      {"an #include found earlier in the -s directories",
       [&] { write_file(root / "early" / "helper.glsl", "uint helper(uint x) { return x + 2u; }\n"); }},
      {"a shader's own text",
       [&] { write_file(root / "a.comp", read_file(root / "a.comp") + "// edited\n"); }},
      {"a notation macro", [&] { edit_notation("\"2u\"", "\"3u\""); }},
      {"a pipeline's name", [&] { edit_notation("\"Name\": \"B\"", "\"Name\": \"B2\""); }},
      {"an inline source", [&] { edit_notation("data[id.x] = id.x;", "data[id.x] = id.x + 1;"); }},
  };
  for (const auto& [what, apply] : changes) {
    SCOPED_TRACE(what);
    apply();
    pack("changed.spk", "", true, true);
    EXPECT_EQ(last_output_.find(kReused), std::string::npos) << last_output_;
    EXPECT_EQ(read_file(dir_ / "changed.spk"), clean_bytes());
    pack("again.spk", "", true, true);
    EXPECT_NE(last_output_.find(kReused), std::string::npos) << last_output_;
    EXPECT_EQ(read_file(dir_ / "again.spk"), read_file(dir_ / "changed.spk"));
  }
  for (const char* option : {"-D UNUSED_BY_ALL=1", "--vulkan_version 1.1", "--optimize size", "--strict"}) {
    SCOPED_TRACE(option);
    pack("option.spk", option, true, true);
    EXPECT_EQ(last_output_.find(kReused), std::string::npos) << last_output_;
    EXPECT_EQ(read_file(dir_ / "option.spk"), clean_bytes(option));
    pack("option_again.spk", option, true, true);
    EXPECT_NE(last_output_.find(kReused), std::string::npos) << last_output_;
  }
}

// A damaged record, or a link planted in its place, is not used; the pack writes it again.
TEST_F(CompileCacheTest, ADamagedArchiveRecordIsNotUsed) {
  pack("first.spk", "", true, true);
  const std::string archive = read_file(dir_ / "first.spk");
  const fs::path record = entry_holding(archive);
  ASSERT_FALSE(record.empty()) << "no entry holds the archive";
  std::string bytes = read_file(record);
  bytes[bytes.size() - 5] ^= 0x10;  // one bit of the archive's copy
  write_file(record, bytes);
  pack("damaged.spk", "", true, true);
  EXPECT_EQ(last_output_.find(kReused), std::string::npos) << last_output_;
  EXPECT_EQ(read_file(dir_ / "damaged.spk"), archive);
  pack("healed.spk", "", true, true);
  EXPECT_NE(last_output_.find(kReused), std::string::npos) << last_output_;
  EXPECT_EQ(read_file(dir_ / "healed.spk"), archive);
  fs::remove(record);
  fs::create_symlink(dir_ / "first.spk", record);  // never read through
  pack("planted.spk", "", true, true);
  EXPECT_EQ(last_output_.find(kReused), std::string::npos) << last_output_;
  EXPECT_EQ(read_file(dir_ / "planted.spk"), archive);
  EXPECT_FALSE(fs::is_symlink(record));  // replaced by the new record
}

// A pack that prints a note or warning is not recorded: the next pack prints it again.
TEST_F(CompileCacheTest, APackThatPrintsANoteIsNotRecorded) {
  std::string json = read_file(dir_ / "project.json");
  json.insert(
      1,
      R"("ResourceSignatures": [{"Name": "Unused", "Resources": [{"Name": "other", "ShaderStages": "COMPUTE", "ResourceType": "BUFFER_UAV"}]}], )");
  write_file(dir_ / "project.json", json);
  pack("first.spk", "", true, true);
  ASSERT_NE(last_output_.find("used by no pipeline"), std::string::npos) << last_output_;
  pack("second.spk", "", true, true);
  EXPECT_EQ(last_output_.find(kReused), std::string::npos) << last_output_;
  EXPECT_NE(last_output_.find("used by no pipeline"), std::string::npos) << last_output_;
  EXPECT_EQ(read_file(dir_ / "second.spk"), read_file(dir_ / "first.spk"));
}

// --- input stamps (input_stamps.hpp): a repack whose inputs all stat as stamped reads none of them ---

constexpr const char* kStamped = "(every input stats as stamped)";

// A file is stamped only once it is older than the racy window (two seconds) when a pack starts: the
// tests wait that long where they need stamps.
static void wait_out_the_racy_window() {
  std::this_thread::sleep_for(std::chrono::milliseconds(2100));
}

TEST_F(CompileCacheTest, AnUnchangedProjectReadsNothingWhenEveryInputStatsAsStamped) {
  wait_out_the_racy_window();
  pack("first.spk", "--depfile first.d", true, true);
  EXPECT_EQ(last_output_.find(kReused), std::string::npos) << last_output_;
  pack("second.spk", "--depfile second.d", true, true);
  EXPECT_NE(last_output_.find(kStamped), std::string::npos) << last_output_;
  EXPECT_EQ(last_output_.find("time: read notation"), std::string::npos) << last_output_;
  EXPECT_EQ(read_file(dir_ / "second.spk"), clean_bytes());
  std::string expected = read_file(dir_ / "first.d");  // every file, #includes too
  expected.replace(expected.find("first.spk"), 9, "second.spk");
  EXPECT_EQ(read_file(dir_ / "second.d"), expected);
  expect_an_output_linked_to_refused("b.comp");
}

// An edit loop packs within seconds of each edit, inside the racy window: each pack's stamps vouch for
// nothing (unsettled), yet the next pack builds glslang's tables from their hint before it reads its
// notation (compiler_warmup.hpp), as --time-report says. Until 0.5.6 such a pack wrote no stamps, and
// the next built its tables only once its notation was read. The archive is the same either way.
TEST_F(CompileCacheTest, AnEditLoopBuildsTheCompilersTablesAheadFromTheLastPacksStamps) {
  constexpr const char* kAhead = "tables built ahead on another core, from the input stamps' hint";
  const bool two_cores = std::thread::hardware_concurrency() >= 2;  // (one core: never built ahead)
  pack("first.spk", "", true, true);
  for (int edit = 1; edit <= 3; ++edit) {
    SCOPED_TRACE(edit);
    write_file(dir_ / "a.comp", read_file(dir_ / "a.comp") + "// edit " + std::to_string(edit) + "\n");
    pack("edited.spk", edit == 3 ? "-t 1" : "", true, true);  // -t 1: no other core to build on
    EXPECT_EQ(last_output_.find(kAhead) != std::string::npos, two_cores && edit < 3) << last_output_;
    EXPECT_EQ(last_output_.find(kStamped), std::string::npos) << last_output_;
    EXPECT_EQ(read_file(dir_ / "edited.spk"), clean_bytes());
  }
}

// Every change of a file's bytes, of where a name is found, or of the options misses the stamps: the pack
// reads its inputs (and reuses the record only when their bytes are the same), and stamps them again
// once they are older than the racy window. A file written within that window is never trusted by stat.
TEST_F(CompileCacheTest, AnyChangeOfAnInputOrOfWhereItIsFoundMissesTheStamps) {
  // A fourth pipeline whose shader is found in an -s directory: a file of that name put in an earlier
  // one is found instead.
  std::string json = read_file(dir_ / "project.json");
  json.replace(json.rfind("]}"), 2,
               R"(, {"PSODesc": {"Name": "C"}, "pCS": {"Desc": {"Name": "C CS"}, "FilePath": "c.comp"}}]})");
  write_file(dir_ / "project.json", json);
  const std::string c_shader =
      "#version 450\nlayout(local_size_x = 8) in;\nlayout(set = 0, binding = 0) buffer Data { uint v[]; } "
      "data;\nvoid main() { data.v[gl_GlobalInvocationID.x] = 7u; }\n";
  write_file(dir_ / "inc" / "c.comp", c_shader);
  // The notation given through a link (read under its canonical name).
  fs::rename(dir_ / "project.json", dir_ / "project_v1.json");
  fs::create_symlink("project_v1.json", dir_ / "project.json");
  wait_out_the_racy_window();
  pack("first.spk", "", true, true);
  pack("stamped.spk", "", true, true);
  ASSERT_NE(last_output_.find(kStamped), std::string::npos) << last_output_;

  const fs::path root = dir_;
  struct Change {
    const char* what;
    std::function<void()> apply;
    bool same_bytes;  // the record still holds once the files are read
  };
  const Change changes[] = {
      {"an #include's text, same size",
       [&] { write_file(root / "common.glsl", "uint twice(uint x) { return x * 2u; }\n"); }, false},
      {"a shader touched, its text the same",
       [&] { fs::last_write_time(root / "b.comp", fs::file_time_type::clock::now()); }, true},
      {"a shader replaced by a link to a copy of it",
       [&] {
         fs::copy_file(root / "a.comp", root / "a_copy.comp");
         fs::remove(root / "a.comp");
         fs::create_symlink("a_copy.comp", root / "a.comp");
       },
       true},
      {"a shader found earlier in the -s directories",
       [&] { write_file(root / "early" / "c.comp", c_shader + "// early\n"); }, false},
      {"an #include found earlier in the -s directories",
       [&] { write_file(root / "early" / "helper.glsl", "uint helper(uint x) { return x + 2u; }\n"); },
       false},
      {"the notation's link pointed at another file",
       [&] {
         std::string v2 = read_file(root / "project_v1.json");
         v2.replace(v2.find("\"Name\": \"B\""), 11, "\"Name\": \"B2\"");
         write_file(root / "project_v2.json", v2);
         fs::remove(root / "project.json");
         fs::create_symlink("project_v2.json", root / "project.json");
       },
       false},
  };
  for (const auto& [what, apply, same_bytes] : changes) {
    SCOPED_TRACE(what);
    apply();
    pack("changed.spk", "", true, true);
    EXPECT_EQ(last_output_.find(kStamped), std::string::npos) << last_output_;
    EXPECT_EQ(last_output_.find(kReused) != std::string::npos, same_bytes) << last_output_;
    EXPECT_EQ(read_file(dir_ / "changed.spk"), clean_bytes());
    // Changed within the racy window of that pack: not stamped yet, whatever the next pack finds.
    pack("racy.spk", "", true, true);
    EXPECT_EQ(last_output_.find(kStamped), std::string::npos) << last_output_;
    EXPECT_NE(last_output_.find(kReused), std::string::npos) << last_output_;
    wait_out_the_racy_window();
    pack("restamped.spk", "", true, true);
    pack("stamped.spk", "", true, true);
    EXPECT_NE(last_output_.find(kStamped), std::string::npos) << last_output_;
    EXPECT_EQ(read_file(dir_ / "stamped.spk"), read_file(dir_ / "changed.spk"));
  }
  pack("option.spk", "--strict", true, true);  // the options are part of what the stamps vouch for
  EXPECT_EQ(last_output_.find(kStamped), std::string::npos) << last_output_;
  EXPECT_EQ(read_file(dir_ / "option.spk"), clean_bytes("--strict"));
}

// Stamps vouch for the record they were written with: the project's record replaced by another one with
// the same inputs key (the key leaves #includes out), as a pack that read an #include's older text and
// ended last would leave it, is not written on the stamps' word.
TEST_F(CompileCacheTest, StampsVouchForTheirOwnRecordOnly) {
  wait_out_the_racy_window();
  pack("old.spk", "", true, true);
  const std::string old_archive = read_file(dir_ / "old.spk");
  const fs::path record = entry_holding(old_archive);
  ASSERT_FALSE(record.empty()) << "no entry holds the archive";
  const std::string old_record = read_file(record);
  write_file(dir_ / "common.glsl", "uint twice(uint x) { return x + x; }\n");  // a new #include text
  wait_out_the_racy_window();
  pack("new.spk", "", true, true);  // records it and stamps it
  pack("stamped.spk", "", true, true);
  ASSERT_NE(last_output_.find(kStamped), std::string::npos) << last_output_;
  ASSERT_NE(read_file(dir_ / "new.spk"), old_archive);
  fs::remove(record);
  write_file(record, old_record);  // the other pack's record, written last
  pack("after.spk", "", true, true);
  EXPECT_EQ(last_output_.find(kStamped), std::string::npos) << last_output_;
  EXPECT_EQ(read_file(dir_ / "after.spk"), read_file(dir_ / "new.spk"));
}
