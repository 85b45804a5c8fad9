// statepack pack --remote-cache: one compile shared by every checkout and machine, through servers
// started here on loopback ports (Debian's nginx with WebDAV PUT, redis-server, a shared directory).
// A second checkout at another path packs with zero compiles and the same bytes; a server that is down,
// slow, failing or serving damaged, planted or unsigned entries never fails a pack and never gets an
// entry used that fails its check; shards and --no-compile assemble the same archive.
#include <gtest/gtest.h>

#include <chrono>
#include <filesystem>
#include <regex>
#include <string>
#include <thread>

#include "common/loopback_server.hpp"
#include "common/run_command.hpp"
#include "common/text_files.hpp"

namespace {

namespace fs = std::filesystem;
using statepack::testing::CommandResult;
using statepack::testing::LoopbackServer;
using statepack::testing::read_file;
using statepack::testing::run_command;
using statepack::testing::write_file;

struct PackRun {
  int exit_code = -1;
  std::string output;
  int hits = -1, misses = -1;                                                         // the pack's cache line
  int remote_hits = -1, remote_misses = -1, refused = -1, errors = -1, written = -1;  // its remote part
};

class RemoteCacheTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = statepack::testing::fresh_test_dir(STATEPACK_TEST_OUTPUT_DIR, "remote_cache");
    make_checkout(dir_ / "first");
  }

  // A project: two compute shaders sharing an #include (one more found in an -s directory) and an
  // inline HLSL shader.
  static void make_checkout(const fs::path& at) {
    write_file(at / "project.json", R"({"Pipelines": [
      {"PSODesc": {"Name": "A"}, "pCS": {"Desc": {"Name": "A CS"}, "FilePath": "a.comp"}},
      {"PSODesc": {"Name": "B"}, "pCS": {"Desc": {"Name": "B CS"}, "FilePath": "b.comp"}},
      {"PSODesc": {"Name": "H"}, "pCS": {"Desc": {"Name": "H CS"}, "SourceLanguage": "HLSL",
        "Source": "RWStructuredBuffer<uint> data;\n[numthreads(4, 1, 1)] void main(uint3 id : SV_DispatchThreadID) { data[id.x] = id.x; }\n"}}]})");
    write_file(at / "common.glsl", "uint twice(uint x) { return 2u * x; }\n");
    write_file(at / "a.comp",
               "#version 450\n#extension GL_GOOGLE_include_directive : require\n#include \"common.glsl\"\n"
               "layout(local_size_x = 64) in;\nlayout(set = 0, binding = 0) buffer Data { uint v[]; } data;\n"
               "void main() { data.v[gl_GlobalInvocationID.x] = twice(gl_GlobalInvocationID.x); }\n");
    write_file(at / "b.comp",
               "#version 450\n#extension GL_GOOGLE_include_directive : require\n#include \"helper.glsl\"\n"
               "layout(local_size_x = 32) in;\nlayout(set = 0, binding = 0) buffer Data { uint v[]; } data;\n"
               "void main() { data.v[gl_GlobalInvocationID.x] = helper(gl_GlobalInvocationID.x); }\n");
    write_file(at / "inc" / "helper.glsl", "uint helper(uint x) { return x + 1u; }\n");
  }

  // Packs `checkout` (its own local cache unless `extra` says otherwise) with `env` before the command.
  // The -s directory is given by absolute path, as a CMake project gives it. The archive record is off: a
  // record is local, and these tests check what the shaders' entries do.
  PackRun pack(const fs::path& checkout, const std::string& out, const std::string& extra,
               const std::string& env = "") {
    const CommandResult r =
        run_command("cd '" + checkout.string() + "' && " + env +
                    " '" STATEPACK_EXE "' pack -i project.json -s '" + (checkout / "inc").string() +
                    "' -o '" + out + "' --vulkan --time-report --no-archive-reuse " + extra);
    PackRun run{r.exit_code, r.output};
    static const std::regex cache(R"(cache: (\d+) hits, (\d+) misses)");
    static const std::regex remote(
        R"(remote: (\d+) hits, (\d+) misses, (\d+) refused, (\d+) errors, (\d+) written)");
    std::smatch m;
    if (std::regex_search(r.output, m, cache)) run.hits = std::stoi(m[1]), run.misses = std::stoi(m[2]);
    if (std::regex_search(r.output, m, remote))
      run.remote_hits = std::stoi(m[1]), run.remote_misses = std::stoi(m[2]), run.refused = std::stoi(m[3]),
      run.errors = std::stoi(m[4]), run.written = std::stoi(m[5]);
    return run;
  }
  std::string clean_archive() {
    const CommandResult r = run_command("cd '" + (dir_ / "first").string() +
                                        "' && '" STATEPACK_EXE "' pack -i project.json -s inc -o '" +
                                        (dir_ / "clean.spk").string() + "' --vulkan");
    EXPECT_EQ(r.exit_code, 0) << r.output;
    return read_file(dir_ / "clean.spk");
  }
  // A second checkout of the same project at another path.
  fs::path second_checkout() {
    make_checkout(dir_ / "elsewhere" / "second");
    return dir_ / "elsewhere" / "second";
  }
  // Every entry file below `root` (64 hex digits).
  static std::vector<fs::path> entries_below(const fs::path& root) {
    std::vector<fs::path> out;
    if (!fs::exists(root)) return out;
    for (const auto& e : fs::recursive_directory_iterator(root)) {
      const std::string name = e.path().filename().string();
      if (e.is_regular_file() && !name.starts_with(".tmp")) out.push_back(e.path());
    }
    return out;
  }
  // A first pack fills the remote; a second checkout with an empty local cache then packs from it.
  void shared_across_checkouts(const std::string& url) {
    const std::string clean = clean_archive();
    const PackRun cold =
        pack(dir_ / "first", "../a.spk", "--cache-dir ../cache-a --remote-cache '" + url + "'");
    ASSERT_EQ(cold.exit_code, 0) << cold.output;
    EXPECT_EQ(cold.misses, 6) << cold.output;  // three compiles, three finalisations
    EXPECT_EQ(cold.written, 6) << cold.output;
    const fs::path second = second_checkout();
    const PackRun warm = pack(second, "../b.spk", "--cache-dir ../cache-b --remote-cache '" + url + "'");
    ASSERT_EQ(warm.exit_code, 0) << warm.output;
    EXPECT_EQ(warm.misses, 0) << "the second checkout compiled: " << warm.output;
    EXPECT_EQ(warm.remote_hits, 6) << warm.output;
    EXPECT_EQ(warm.written, 0) << warm.output;
    EXPECT_EQ(read_file(dir_ / "a.spk"), clean);
    EXPECT_EQ(read_file(dir_ / "elsewhere" / "b.spk"), clean);
    // What came from the remote is kept locally: the next pack does not ask.
    const PackRun local = pack(second, "../b.spk", "--cache-dir ../cache-b --remote-cache '" + url + "'");
    EXPECT_EQ(local.misses, 0) << local.output;
    EXPECT_EQ(local.remote_hits, 0) << local.output;
  }

  fs::path dir_;
};

TEST_F(RemoteCacheTest, ASecondCheckoutPacksFromNginxWithoutCompiling) {
  LoopbackServer nginx;
  ASSERT_TRUE(nginx.start_nginx(dir_ / "nginx"));
  shared_across_checkouts("http://127.0.0.1:" + std::to_string(nginx.port()) + "/cache");
  // ccache's default layout: ab/cdef... below the URL's path, each one a whole entry.
  const auto entries = entries_below(dir_ / "nginx" / "root" / "cache");
  ASSERT_EQ(entries.size(), 6u);
  for (const auto& e : entries) {
    EXPECT_EQ(e.parent_path().filename().string().size(), 2u);
    const std::string key = e.parent_path().filename().string() + e.filename().string();
    EXPECT_EQ(key.size(), 64u) << key;
    EXPECT_EQ(key.find_first_not_of("0123456789abcdef"), std::string::npos) << key;
    EXPECT_EQ(read_file(e).substr(0, 4), "SPKC");
  }
}

TEST_F(RemoteCacheTest, ASecondCheckoutPacksFromRedisWithoutCompiling) {
  LoopbackServer redis;
  ASSERT_TRUE(redis.start_redis(dir_ / "redis"));
  shared_across_checkouts("redis://127.0.0.1:" + std::to_string(redis.port()));
  const CommandResult keys =
      run_command("redis-cli -p " + std::to_string(redis.port()) + " --scan --pattern 'statepack:*' | wc -l");
  EXPECT_EQ(std::stoi(keys.output), 6) << keys.output;
}

TEST_F(RemoteCacheTest, ASecondCheckoutPacksFromASharedDirectoryWithoutCompiling) {
  shared_across_checkouts("file:" + (dir_ / "shared").string());
  EXPECT_EQ(entries_below(dir_ / "shared").size(), 6u);
}

TEST_F(RemoteCacheTest, AServerThatIsDownCostsOneFailureAndAWarning) {
  const std::string clean = clean_archive();
  const int port = statepack::testing::free_loopback_port();  // nothing listens there
  const auto start = std::chrono::steady_clock::now();
  const PackRun run =
      pack(dir_ / "first", "../a.spk",
           "--cache-dir ../cache --remote-cache 'http://127.0.0.1:" + std::to_string(port) + "/c'");
  const auto took = std::chrono::steady_clock::now() - start;
  ASSERT_EQ(run.exit_code, 0) << run.output;
  EXPECT_GE(run.errors, 1) << run.output;  // (one per connection in flight when the first failed)
  EXPECT_LE(run.errors, 4) << run.output;
  EXPECT_EQ(run.misses, 6) << run.output;
  EXPECT_NE(run.output.find("warning: remote cache 'http://127.0.0.1:"), std::string::npos) << run.output;
  EXPECT_NE(run.output.find("not asked again in this pack"), std::string::npos) << run.output;
  EXPECT_LT(took, std::chrono::seconds(20));
  EXPECT_EQ(read_file(dir_ / "a.spk"), clean);
}

TEST_F(RemoteCacheTest, ASlowServerIsWaitedForOnceThenLeftAlone) {
  const std::string clean = clean_archive();
  LoopbackServer nginx;
  ASSERT_TRUE(nginx.start_nginx(dir_ / "nginx"));
  nginx.pause();  // connections are accepted by the kernel, nothing answers
  const auto start = std::chrono::steady_clock::now();
  const PackRun run =
      pack(dir_ / "first", "../a.spk",
           "--cache-dir ../cache --remote-cache 'http://127.0.0.1:" + std::to_string(nginx.port()) +
               "/c|operation-timeout=300'");
  const auto took = std::chrono::steady_clock::now() - start;
  nginx.resume();
  ASSERT_EQ(run.exit_code, 0) << run.output;
  // One time-out on each connection in flight (one per thread at most), at once; then no request.
  EXPECT_GE(run.errors, 1) << run.output;
  EXPECT_LE(run.errors, 4) << run.output;
  EXPECT_NE(run.output.find("not asked again in this pack"), std::string::npos) << run.output;
  EXPECT_LT(took, std::chrono::seconds(3)) << "more than one time-out's wait: " << run.output;
  EXPECT_NE(run.output.find("imeout"), std::string::npos) << run.output;
  EXPECT_EQ(read_file(dir_ / "a.spk"), clean);
}

TEST_F(RemoteCacheTest, AServerStoppedDuringAPackDoesNotFailIt) {
  const std::string clean = clean_archive();
  LoopbackServer redis;
  ASSERT_TRUE(redis.start_redis(dir_ / "redis"));
  const std::string url = "redis://127.0.0.1:" + std::to_string(redis.port());
  // The server goes away while the pack runs (during its compiles or its writes, whichever comes).
  std::thread stopper([&] {
    std::this_thread::sleep_for(std::chrono::milliseconds(150));
    redis.stop();
  });
  const PackRun run =
      pack(dir_ / "first", "../a.spk", "-t 2 --cache-dir ../cache --remote-cache '" + url + "'");
  stopper.join();
  ASSERT_EQ(run.exit_code, 0) << run.output;
  EXPECT_EQ(read_file(dir_ / "a.spk"), clean);
  // No request is sent to a server after one failed: only those already in flight fail with it, a read
  // on each of the 2 compile threads or one of the 4 writes the flush keeps in flight
  // (RemoteCache::kConnections); a failed read stops the writes too.
  EXPECT_LE(run.errors, 4) << run.output;
}

TEST_F(RemoteCacheTest, RefusedWritesAreReportedAndReadsGoOn) {
  LoopbackServer nginx;
  ASSERT_TRUE(nginx.start_nginx(dir_ / "nginx"));
  const std::string base = "http://127.0.0.1:" + std::to_string(nginx.port());
  for (const char* path : {"/fails", "/missing", "/no-put"}) {
    fs::remove_all(dir_ / "cache");
    const PackRun run =
        pack(dir_ / "first", "../a.spk", "--cache-dir ../cache --remote-cache '" + base + path + "'");
    ASSERT_EQ(run.exit_code, 0) << run.output;
    EXPECT_GE(run.errors, 1) << run.output;  // (one per connection in flight when the first failed)
    EXPECT_LE(run.errors, 4) << run.output;
    EXPECT_EQ(run.written, 0) << run.output;
    EXPECT_NE(run.output.find(std::string("to PUT; not written again in this pack")), std::string::npos)
        << run.output;
  }
  fs::remove_all(dir_ / "cache");
  EXPECT_NE(pack(dir_ / "first", "../a.spk", "--cache-dir ../cache --remote-cache '" + base + "/fails'")
                .output.find("HTTP status 500 to PUT"),
            std::string::npos);
}

TEST_F(RemoteCacheTest, ReadOnlyNeverWrites) {
  LoopbackServer nginx;
  ASSERT_TRUE(nginx.start_nginx(dir_ / "nginx"));
  const PackRun run =
      pack(dir_ / "first", "../a.spk",
           "--cache-dir ../cache --remote-cache 'http://127.0.0.1:" + std::to_string(nginx.port()) +
               "/c|read-only'");
  ASSERT_EQ(run.exit_code, 0) << run.output;
  EXPECT_EQ(run.written, 0) << run.output;
  EXPECT_EQ(run.errors, 0) << run.output;
  EXPECT_TRUE(entries_below(dir_ / "nginx" / "root").empty());
}

// Damaged, truncated, planted (another shader's entry under this one's key) and garbage entries on the
// server are refused with a warning saying why; the shader is compiled here and the archive is the same.
TEST_F(RemoteCacheTest, EntriesThatFailTheirCheckAreNeverUsed) {
  const std::string clean = clean_archive();
  const std::string url = "file:" + (dir_ / "shared").string();
  ASSERT_EQ(pack(dir_ / "first", "../a.spk", "--cache-dir ../cache-a --remote-cache '" + url + "'").exit_code,
            0);
  auto entries = entries_below(dir_ / "shared");
  ASSERT_EQ(entries.size(), 6u);
  std::sort(entries.begin(), entries.end());
  const std::string first = read_file(entries[0]), second = read_file(entries[1]);
  std::string flipped = read_file(entries[2]);
  flipped[flipped.size() - 5] ^= 0x10;
  write_file(entries[0], second);                             // planted: another entry under this name
  write_file(entries[1], first.substr(0, first.size() / 2));  // truncated
  write_file(entries[2], flipped);                            // one bit of its payload
  write_file(entries[3], "garbage");
  const fs::path second_dir = second_checkout();
  const PackRun run = pack(second_dir, "../b.spk", "--cache-dir ../cache-b --remote-cache '" + url + "'");
  ASSERT_EQ(run.exit_code, 0) << run.output;
  EXPECT_EQ(run.refused, 4) << run.output;
  EXPECT_EQ(run.remote_hits, 2) << run.output;
  EXPECT_NE(run.output.find("entries refused (the first, "), std::string::npos) << run.output;
  EXPECT_NE(run.output.find("made here instead"), std::string::npos) << run.output;
  EXPECT_EQ(read_file(dir_ / "elsewhere" / "b.spk"), clean);
}

// A finalised module whose entry is whole (its hash made again over a changed payload, as anyone who can
// write to the server can) but whose SPIR-V fails validation is refused, as a fresh compile's would be.
TEST_F(RemoteCacheTest, AnUnsignedModuleThatFailsValidationIsNeverUsed) {
  const std::string clean = clean_archive();
  const std::string url = "file:" + (dir_ / "shared").string();
  ASSERT_EQ(pack(dir_ / "first", "../a.spk", "--cache-dir ../cache-a --remote-cache '" + url + "'").exit_code,
            0);
  // Each finalisation (payload: u32 count, then SPIR-V from its magic number): its OpMemoryModel's memory
  // model set to 77 (none such), and the header's SHA-256 of the payload made again.
  write_file(dir_ / "forge.py", R"(import hashlib, pathlib, struct, sys
forged = 0
for path in pathlib.Path(sys.argv[1]).rglob('*'):
    data = bytearray(path.read_bytes()) if path.is_file() else b''
    if len(data) < 120 or data[116:120] != bytes.fromhex('03022307'): continue
    words = 116 + 20
    while words + 4 <= len(data):
        op = struct.unpack_from('<I', data, words)[0]
        if op & 0xffff == 14:  # OpMemoryModel
            struct.pack_into('<I', data, words + 8, 77)
            break
        words += 4 * (op >> 16)
    data[48:80] = hashlib.sha256(bytes(data[112:])).digest()
    path.write_bytes(bytes(data))
    forged += 1
print(forged)
)");
  const CommandResult forged =
      run_command("python3 '" + (dir_ / "forge.py").string() + "' '" + (dir_ / "shared").string() + "'");
  ASSERT_EQ(forged.exit_code, 0) << forged.output;
  EXPECT_EQ(std::stoi(forged.output), 3) << forged.output;
  const PackRun run =
      pack(second_checkout(), "../b.spk", "--cache-dir ../cache-b --remote-cache '" + url + "'");
  ASSERT_EQ(run.exit_code, 0) << run.output;
  EXPECT_EQ(run.refused, 3) << run.output;
  EXPECT_NE(run.output.find("its module fails validation"), std::string::npos) << run.output;
  EXPECT_EQ(read_file(dir_ / "elsewhere" / "b.spk"), clean);
}

// With a team key, every entry written is signed and only entries signed with the same key are used.
TEST_F(RemoteCacheTest, OnlyEntriesSignedWithTheTeamKeyAreUsed) {
  const std::string clean = clean_archive();
  const std::string url = "file:" + (dir_ / "shared").string();
  write_file(dir_ / "team.key", "correct horse battery staple\n");
  const std::string team = "STATEPACK_CACHE_KEY_FILE='" + (dir_ / "team.key").string() + "'";
  // Unsigned entries (written without a key) are refused by a pack with one.
  ASSERT_EQ(pack(dir_ / "first", "../a.spk", "--cache-dir ../c1 --remote-cache '" + url + "'").exit_code, 0);
  PackRun run = pack(dir_ / "first", "../a.spk", "--cache-dir ../c2 --remote-cache '" + url + "'", team);
  ASSERT_EQ(run.exit_code, 0) << run.output;
  EXPECT_EQ(run.refused, 6) << run.output;
  EXPECT_NE(run.output.find("not signed with the team's key"), std::string::npos) << run.output;
  // Signed entries (that pack wrote its compiles over the unsigned ones) serve the team ...
  run = pack(dir_ / "first", "../a.spk", "--cache-dir ../c3 --remote-cache '" + url + "'", team);
  EXPECT_EQ(run.remote_hits, 6) << run.output;
  EXPECT_EQ(run.misses, 0) << run.output;
  // ... and are refused under another key.
  run = pack(dir_ / "first", "../a.spk", "--cache-dir ../c4 --remote-cache '" + url + "'",
             "STATEPACK_CACHE_KEY=another");
  EXPECT_EQ(run.refused, 6) << run.output;
  EXPECT_EQ(run.misses, 6) << run.output;
  EXPECT_EQ(read_file(dir_ / "a.spk"), clean);
}

TEST_F(RemoteCacheTest, TwoPacksWritingTheSameEntriesAtOnceLeaveWholeEntries) {
  LoopbackServer nginx;
  ASSERT_TRUE(nginx.start_nginx(dir_ / "nginx"));
  const std::string url = "http://127.0.0.1:" + std::to_string(nginx.port()) + "/c";
  const fs::path second = second_checkout();
  PackRun a, b;
  std::thread other(
      [&] { b = pack(second, "../b.spk", "--cache-dir ../cache-b --remote-cache '" + url + "'"); });
  a = pack(dir_ / "first", "../a.spk", "--cache-dir ../cache-a --remote-cache '" + url + "'");
  other.join();
  ASSERT_EQ(a.exit_code, 0) << a.output;
  ASSERT_EQ(b.exit_code, 0) << b.output;
  const PackRun third =
      pack(dir_ / "first", "../c.spk", "--cache-dir ../cache-c --remote-cache '" + url + "'");
  EXPECT_EQ(third.remote_hits, 6) << third.output;
  EXPECT_EQ(third.refused, 0) << third.output;
  EXPECT_EQ(read_file(dir_ / "c.spk"), clean_archive());
}

// Two shards on two processes fill a shared cache; --no-compile assembles the archive from it without
// compiling, and names every shader it would have had to compile when the cache lacks them.
TEST_F(RemoteCacheTest, ShardsThenNoCompileAssembleTheSameArchive) {
  const std::string clean = clean_archive();
  const std::string url = "--remote-cache 'file:" + (dir_ / "shared").string() + "'";
  const CommandResult missing = run_command(
      "cd '" + (dir_ / "first").string() +
      "' && '" STATEPACK_EXE "' pack -i project.json -s inc -o x.spk --vulkan --no-compile " + url);
  EXPECT_EQ(missing.exit_code, 1) << missing.output;
  for (const char* name : {"'A CS'", "'B CS'", "'H CS'"})
    EXPECT_NE(missing.output.find(std::string("shader ") + name + ": not in the compile cache"),
              std::string::npos)
        << missing.output;
  int compiled = 0;
  for (const char* shard : {"1/2", "2/2"}) {
    const CommandResult r =
        run_command("cd '" + (dir_ / "first").string() +
                    "' && '" STATEPACK_EXE "' pack -i project.json -s inc --vulkan --shard " +
                    std::string(shard) + " --cache-dir ../cache-" + shard[0] + " " + url);
    ASSERT_EQ(r.exit_code, 0) << r.output;
    std::smatch m;
    ASSERT_TRUE(std::regex_search(r.output, m, std::regex(R"(of 3 shader compiles \((\d+) compiled)")))
        << r.output;
    compiled += std::stoi(m[1]);
  }
  EXPECT_EQ(compiled, 3);
  const fs::path second = second_checkout();
  const PackRun assembled = pack(second, "../b.spk", "--no-compile " + url);
  ASSERT_EQ(assembled.exit_code, 0) << assembled.output;
  EXPECT_EQ(read_file(dir_ / "elsewhere" / "b.spk"), clean);
}

// Without a server: entries move as one file (a build artifact); the import checks each one.
TEST_F(RemoteCacheTest, ExportedEntriesImportedElsewhereServeANoCompilePack) {
  const std::string clean = clean_archive();
  ASSERT_EQ(pack(dir_ / "first", "../a.spk", "--cache-dir ../cache-a", "STATEPACK_CACHE_KEY=team").exit_code,
            0);
  const std::string sp = "'" STATEPACK_EXE "' cache ";
  const std::string a = (dir_ / "cache-a").string(), b = (dir_ / "cache-b").string(),
                    x = (dir_ / "x.spkx").string();
  // A link planted among the entries under an entry's name (to a file of the exporting user) is left out.
  write_file(dir_ / "private.txt", "not for export");
  fs::create_directories(dir_ / "cache-a" / "v2" / "ab");
  fs::create_symlink(dir_ / "private.txt", dir_ / "cache-a" / "v2" / "ab" / ("ab" + std::string(62, 'c')));
  CommandResult r = run_command(sp + "export '" + a + "' '" + x + "'");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find(": 7 entries"), std::string::npos) << r.output;  // six and the pack's bundle
  EXPECT_EQ(read_file(x).find("not for export"), std::string::npos);
  r = run_command("STATEPACK_CACHE_KEY=other " + sp + "import '" + b + "' '" + x + "'");
  EXPECT_EQ(r.exit_code, 1) << r.output;  // signed with another key: every entry refused
  EXPECT_NE(r.output.find("0 entries, 0 bytes imported; 0 already present, 7 refused"), std::string::npos)
      << r.output;
  r = run_command("STATEPACK_CACHE_KEY=team " + sp + "import '" + b + "' '" + x + "'");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const fs::path second = second_checkout();
  const PackRun run =
      pack(second, "../b.spk", "--no-compile --cache-dir ../../cache-b", "STATEPACK_CACHE_KEY=team");
  ASSERT_EQ(run.exit_code, 0) << run.output;
  EXPECT_EQ(run.misses, 0) << run.output;
  EXPECT_EQ(read_file(dir_ / "elsewhere" / "b.spk"), clean);
  // A file that is not an export, or one cut short, is an error naming it; the entries before the cut stay.
  write_file(dir_ / "garbage.spkx", "not an export");
  r = run_command(sp + "import '" + b + "' '" + (dir_ / "garbage.spkx").string() + "'");
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_NE(r.output.find("is not an export of a statepack cache"), std::string::npos) << r.output;
  write_file(dir_ / "cut.spkx", read_file(x).substr(0, read_file(x).size() - 100));
  r = run_command(sp + "import '" + (dir_ / "cache-c").string() + "' '" + (dir_ / "cut.spkx").string() + "'");
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_NE(r.output.find("is truncated or damaged after 6 entries"), std::string::npos) << r.output;
}

// What a hermetic build declares: every file a pack reads, #includes found through -s included, named
// relative to the working directory (the same list in every checkout).
TEST_F(RemoteCacheTest, ListInputsNamesEveryFileThePackReads) {
  for (const fs::path& checkout : {dir_ / "first", second_checkout()}) {
    const CommandResult r =
        run_command("cd '" + checkout.string() + "' && '" STATEPACK_EXE "' pack -i project.json -s '" +
                    (checkout / "inc").string() + "' --vulkan --check --list-inputs");
    ASSERT_EQ(r.exit_code, 0) << r.output;
    EXPECT_EQ(r.output, "a.comp\nb.comp\ncommon.glsl\ninc/helper.glsl\nproject.json\n");
  }
}

// --shard needs somewhere to put its compiles: a --cache-dir that cannot be used (a file in its place)
// and no server is an error, not a crash; only read-only servers is a usage error.
TEST_F(RemoteCacheTest, AShardWithNowhereToWriteIsAnError) {
  write_file(dir_ / "not-a-directory", "x");
  const std::string in_first = "cd '" + (dir_ / "first").string() +
                               "' && '" STATEPACK_EXE "' pack -i project.json -s inc --vulkan --shard 1/2 ";
  CommandResult r = run_command(in_first + "--cache-dir ../not-a-directory");
  EXPECT_EQ(r.exit_code, 3) << r.output;
  EXPECT_NE(r.output.find("there is none to write to"), std::string::npos) << r.output;
  r = run_command(in_first + "--remote-cache 'file:../s|read-only'");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("every one given is read-only"), std::string::npos) << r.output;
}

TEST_F(RemoteCacheTest, UsageErrorsExitTwo) {
  for (const char* args :
       {"--remote-cache 'ftp://host/x'", "--remote-cache 'http://'", "--remote-cache 'http://h:99999/'",
        "--remote-cache 'http://h/|read-onl'", "--remote-cache 'http://h/|connect-timeout=x'",
        "--remote-cache 'http://h/*'", "--remote-cache 'redis://h/x'", "--shard 0/2 --cache-dir c",
        "--shard 3/2 --cache-dir c", "--shard 1/0 --cache-dir c", "--shard 1 --cache-dir c", "--shard 1/2",
        "--no-compile", "--shard 1/2 --no-compile --cache-dir c"}) {
    const CommandResult r =
        run_command("cd '" + (dir_ / "first").string() +
                    "' && '" STATEPACK_EXE "' pack -i project.json --vulkan --check " + std::string(args));
    EXPECT_EQ(r.exit_code, 2) << args << ": " << r.output;
    EXPECT_NE(r.output.find("error:"), std::string::npos) << args << ": " << r.output;
  }
  const CommandResult env = run_command("cd '" + (dir_ / "first").string() +
                                        "' && STATEPACK_REMOTE_CACHE=nonsense '" STATEPACK_EXE
                                        "' pack -i project.json --vulkan --check");
  EXPECT_EQ(env.exit_code, 2) << env.output;
  EXPECT_NE(env.output.find("STATEPACK_REMOTE_CACHE"), std::string::npos) << env.output;
}

}  // namespace
