// statepack pack --watch as a developer runs it: a child process repacking a small project while the
// test edits it. Each case checks the archive's content (the SPIR-V carries marker constants from the
// shader and its #include; the pipelines' names from `inspect --json`; the bytes equal a one-shot pack of
// the same files), not only the line printed; and ends the watch with SIGINT: exit 0, no temporary left.
#include <fcntl.h>
#include <gtest/gtest.h>
#include <poll.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <regex>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "common/run_command.hpp"
#include "common/text_files.hpp"

namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;
using statepack::testing::run_command;

using statepack::testing::read_file;
using statepack::testing::write_file;  // a save that truncates the file and writes it again
// A save by rename: a temporary beside the file, renamed over it (vim, VS Code, Emacs' backups).
void save_by_rename(const fs::path& path, const std::string& text) {
  const fs::path temporary = fs::path(path) += ".swp";
  write_file(temporary, text);
  fs::rename(temporary, path);
}
void sleep_ms(int ms) {
  std::this_thread::sleep_for(std::chrono::milliseconds(ms));
}

// The shader: its own marker in v[1] (SHADER_MARK), its #include's in v[0] (kValue), optionally more
// #includes, and a line 6 that a test breaks.
std::string shader(uint32_t mark, const std::string& more_includes = "", const std::string& body = "") {
  std::ostringstream text;
  text << "#version 450\n#extension GL_GOOGLE_include_directive : require\n#include \"inc/common.glsl\"\n"
       << more_includes << "layout(local_size_x = 1) in;\n#define SHADER_MARK 0x" << std::hex << mark
       << "u\nlayout(set = 0, binding = 0) buffer Data { uint v[]; } data;\n"
       << "void main() { data.v[0] = kValue; data.v[1] = SHADER_MARK; " << body << "}\n";
  return text.str();
}
std::string include(uint32_t value, const std::string& name = "kValue") {
  std::ostringstream text;
  text << "const uint " << name << " = 0x" << std::hex << value << "u;\n";
  return text.str();
}
std::string compute_pipeline(const std::string& name, const std::string& file) {
  return R"({"PSODesc": {"Name": ")" + name + R"("}, "pCS": {"Desc": {"Name": ")" + name +
         R"( CS", "ShaderType": "COMPUTE"}, "FilePath": ")" + file + R"("}})";
}
std::string notation(const std::vector<std::string>& pipelines) {
  std::string text = "{\n  \"Pipelines\": [\n";
  for (size_t i = 0; i < pipelines.size(); ++i) text += (i ? ",\n    " : "    ") + pipelines[i];
  return text + "\n  ]\n}\n";
}

constexpr uint32_t kShaderMark = 0x5EED1000, kIncludeMark = 0x5EED2000;

class Watch : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = statepack::testing::fresh_test_dir(STATEPACK_TEST_OUTPUT_DIR, "watch");
    write_file(dir_ / "inc" / "common.glsl", include(kIncludeMark));
    write_file(dir_ / "cs.comp", shader(kShaderMark));
    write_file(dir_ / "a.json", notation({compute_pipeline("P", "cs.comp")}));
  }
  void TearDown() override {
    if (pid_ > 0) {
      ::kill(pid_, SIGKILL);
      ::waitpid(pid_, nullptr, 0);
    }
    if (fd_ >= 0) ::close(fd_);
  }

  // Starts `statepack pack --watch` in the project, stdout and stderr into one pipe; waits for the first
  // pack's line.
  void start(const std::vector<std::string>& extra = {"--watch-quiet-ms", "50"}, bool three_files = true) {
    std::vector<std::string> args = {STATEPACK_EXE, "pack",    "-i",       "a.json",
                                     "-o",          "out.spk", "--vulkan", "--watch"};
    args.insert(args.end(), extra.begin(), extra.end());
    std::vector<char*> argv;
    for (auto& a : args) argv.push_back(a.data());
    argv.push_back(nullptr);
    int fds[2];
    ASSERT_EQ(::pipe2(fds, O_CLOEXEC), 0);
    const std::string dir = dir_.string();
    pid_ = ::fork();
    ASSERT_GE(pid_, 0);
    if (pid_ == 0) {  // only async-signal-safe calls until exec
      if (::chdir(dir.c_str()) != 0 || ::dup2(fds[1], 1) < 0 || ::dup2(fds[1], 2) < 0) ::_exit(127);
      ::execv(argv[0], argv.data());
      ::_exit(127);
    }
    ::close(fds[1]);
    fd_ = fds[0];
    ::fcntl(fd_, F_SETFL, O_NONBLOCK);
    const std::string first = next_line("packed ");
    ASSERT_FALSE(first.empty()) << log_;
    if (three_files) {
      EXPECT_TRUE(
          std::regex_match(first, std::regex(R"(packed out\.spk in \d+\.\d{3} s; watching 3 file\(s\) in 2 )"
                                             R"(directories \(Ctrl-C to stop\))")))
          << first;
    }
    first_archive_ = archive();
  }

  // Reads what the child printed for up to `ms`; false at its end of output.
  bool read_some(int ms) {
    pollfd p{fd_, POLLIN, 0};
    if (::poll(&p, 1, ms) <= 0) return true;
    char buffer[4096];
    const ssize_t n = ::read(fd_, buffer, sizeof buffer);
    if (n > 0) log_.append(buffer, size_t(n));
    return n != 0;
  }

  // The next line that starts with `prefix` (within `seconds`), or "" on time-out. `context_` is what was
  // printed between the previous such line and this one (the errors of a failed pack).
  std::string next_line(const std::string& prefix, double seconds = 5) {
    const auto deadline = Clock::now() + std::chrono::duration<double>(seconds);
    size_t scan = cursor_;
    for (;;) {
      for (size_t end; (end = log_.find('\n', scan)) != std::string::npos; scan = end + 1)
        if (log_.compare(scan, prefix.size(), prefix) == 0) {
          context_ = log_.substr(cursor_, scan - cursor_);
          cursor_ = end + 1;
          return log_.substr(scan, end - scan);
        }
      const auto left =
          std::chrono::duration_cast<std::chrono::milliseconds>(deadline - Clock::now()).count();
      if (left <= 0 || !read_some(int(left))) return "";
    }
  }

  // Sends `signal`; the exit code (-1 when it did not exit by itself within 10 s).
  int stop(int signal = SIGINT) {
    ::kill(pid_, signal);
    const auto deadline = Clock::now() + std::chrono::seconds(10);
    while (Clock::now() < deadline && read_some(100)) {
    }
    ::close(fd_);
    fd_ = -1;
    int status = 0;
    while (::waitpid(pid_, &status, WNOHANG) == 0) {
      if (Clock::now() > deadline) return -1;  // TearDown kills it
      sleep_ms(10);
    }
    pid_ = -1;
    return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  }

  // Ends the watch as Ctrl-C does: exit 0, and nothing beside the archive but what the test wrote.
  void finish() {
    EXPECT_EQ(stop(SIGINT), 0) << log_;
    EXPECT_NE(log_.find("stopped by SIGINT"), std::string::npos) << log_;
    expect_no_temporaries();
  }
  void expect_no_temporaries() {
    for (const auto& entry : fs::recursive_directory_iterator(dir_)) {
      const std::string name = entry.path().filename().string();
      EXPECT_TRUE(name.find("statepack-tmp") == std::string::npos && !name.starts_with(".")) << entry.path();
    }
  }

  std::string archive() const { return read_file(dir_ / "out.spk"); }
  // Whether the archive's SPIR-V holds the 32-bit constant `word`.
  bool archive_has(uint32_t word) const {
    const std::string bytes = archive();
    char le[4];
    for (int i = 0; i < 4; ++i) le[i] = char(word >> (8 * i));
    return bytes.find(std::string(le, 4)) != std::string::npos;
  }
  // Waits (up to 5 s) for the archive to hold `word`: a repack line may come before the test looks.
  bool archive_gets(uint32_t word) const {
    const auto deadline = Clock::now() + std::chrono::seconds(5);
    while (!archive_has(word)) {
      if (Clock::now() > deadline) return false;
      sleep_ms(20);
    }
    return true;
  }
  // The bytes a one-shot pack of the same files writes.
  std::string fresh_pack(const std::string& extra = "") const {
    const fs::path fresh = fs::path(dir_) += ".fresh.spk";  // outside the watched project
    auto run = run_command("cd '" + dir_.string() + "' && '" STATEPACK_EXE "' pack -i a.json -o '" +
                           fresh.string() + "' --vulkan " + extra);
    EXPECT_EQ(run.exit_code, 0) << run.output;
    return read_file(fresh);
  }
  std::vector<std::string> pipelines() const {
    auto run = run_command("'" STATEPACK_EXE "' inspect --json '" + (dir_ / "out.spk").string() + "'");
    EXPECT_EQ(run.exit_code, 0) << run.output;
    std::vector<std::string> names;
    auto json = nlohmann::json::parse(run.output, nullptr, false);
    if (json.is_object())
      for (const auto& p : json["pipelines"]) names.push_back(p["name"].get<std::string>());
    return names;
  }
  bool alive() const { return pid_ > 0 && ::waitpid(pid_, nullptr, WNOHANG) == 0; }
  size_t count(const std::string& prefix) const {
    size_t n = log_.starts_with(prefix) ? 1 : 0;
    for (size_t at = log_.find("\n" + prefix); at != std::string::npos; at = log_.find("\n" + prefix, at + 1))
      ++n;
    return n;
  }

  fs::path dir_;
  pid_t pid_ = -1;
  int fd_ = -1;
  std::string log_, context_, first_archive_;
  size_t cursor_ = 0;
};

TEST_F(Watch, ShaderEditRepacksWithTheNewSpirv) {
  ASSERT_NO_FATAL_FAILURE(start());
  EXPECT_TRUE(archive_has(kShaderMark + 0) && archive_has(kIncludeMark));
  write_file(dir_ / "cs.comp", shader(kShaderMark + 1));
  const std::string line = next_line("repacked ");
  EXPECT_TRUE(
      std::regex_match(line, std::regex(R"(repacked out\.spk in \d+\.\d{3} s \(changed: cs\.comp\))")))
      << log_;
  EXPECT_TRUE(archive_has(kShaderMark + 1));
  EXPECT_FALSE(archive_has(kShaderMark + 0));
  EXPECT_EQ(archive(), fresh_pack());
  finish();
}

// What a repack keeps from the last pack (repack_memo.hpp: the notation, each file's text, each compile)
// is taken only while it holds: here every file is older than the racy window, so the first pack keeps
// all of it, and the repacks after an edit of cs.comp take the rest from memory (the time report says
// the notation was kept). A file that appears earlier in a search, which no watch sees, must still
// count: an #include of r.comp found next to it instead of in -s lib, then a shader file the notation
// names found next to the notation instead of in lib. Each archive is a one-shot pack's bytes.
TEST_F(Watch, WhatTheLastPackKeptServesOnlyWhileItHolds) {
  write_file(dir_ / "r.comp",
             "#version 450\n#extension GL_GOOGLE_include_directive : require\n"
             "#include \"shadowed.glsl\"\nlayout(local_size_x = 1) in;\n"
             "layout(set = 0, binding = 0) buffer Data { uint v[]; } data;\n"
             "void main() { data.v[0] = kShadow; }\n");
  write_file(dir_ / "lib" / "shadowed.glsl", include(0x5EED5000, "kShadow"));
  write_file(dir_ / "lib" / "q.comp", shader(0x5EED6000));
  write_file(dir_ / "lib" / "inc" / "common.glsl", include(kIncludeMark));
  write_file(dir_ / "a.json", notation({compute_pipeline("P", "cs.comp"), compute_pipeline("Q", "q.comp"),
                                        compute_pipeline("R", "r.comp")}));
  sleep_ms(2200);  // every file older than the racy window: trusted by the first pack's stamps
  ASSERT_NO_FATAL_FAILURE(start({"--watch-quiet-ms", "50", "-s", "lib", "--time-report"}, false));
  const std::string kept = "read notation (unchanged since the last pack: kept)";
  write_file(dir_ / "cs.comp", shader(kShaderMark + 1));
  EXPECT_NE(next_line("repacked "), "") << log_;
  EXPECT_NE(context_.find(kept), std::string::npos) << context_;
  EXPECT_TRUE(archive_has(kShaderMark + 1) && archive_has(0x5EED5000) && archive_has(0x5EED6000));
  EXPECT_EQ(archive(), fresh_pack("-s lib"));
  // r.comp's #include now found next to it: r.comp and its old #include are unchanged, yet recompiled.
  write_file(dir_ / "shadowed.glsl", include(0x5EED5001, "kShadow"));
  write_file(dir_ / "cs.comp", shader(kShaderMark + 2));
  EXPECT_NE(next_line("repacked "), "") << log_;
  EXPECT_NE(context_.find(kept), std::string::npos) << context_;
  EXPECT_TRUE(archive_has(0x5EED5001));
  EXPECT_FALSE(archive_has(0x5EED5000));
  EXPECT_EQ(archive(), fresh_pack("-s lib"));
  // q.comp now found next to the notation: the notation is read again.
  write_file(dir_ / "q.comp", shader(0x5EED6001));
  write_file(dir_ / "cs.comp", shader(kShaderMark + 3));
  EXPECT_NE(next_line("repacked "), "") << log_;
  EXPECT_EQ(context_.find(kept), std::string::npos) << context_;
  EXPECT_TRUE(archive_has(0x5EED6001));
  EXPECT_FALSE(archive_has(0x5EED6000));
  EXPECT_EQ(archive(), fresh_pack("-s lib"));
  finish();
}

// The notation the last pack kept is not taken when the -i name now leads to another file: here a.json is
// a link to configs/v1.json, pointed at configs/v2.json (as `ln -sfn` does); v1.json itself is unchanged.
TEST_F(Watch, ANotationLinkPointedElsewhereIsReadAgain) {
  write_file(dir_ / "configs" / "v1.json", notation({compute_pipeline("One", "cs.comp")}));
  write_file(dir_ / "configs" / "v2.json", notation({compute_pipeline("Two", "cs.comp")}));
  fs::remove(dir_ / "a.json");
  fs::create_symlink(fs::path("configs") / "v1.json", dir_ / "a.json");
  sleep_ms(2200);  // every file older than the racy window: trusted by the first pack's stamps
  ASSERT_NO_FATAL_FAILURE(start({"--watch-quiet-ms", "50", "-s", ".", "--time-report"}, false));
  EXPECT_EQ(pipelines(), std::vector<std::string>{"One"});
  fs::create_symlink(fs::path("configs") / "v2.json", dir_ / "a.json.new");
  fs::rename(dir_ / "a.json.new", dir_ / "a.json");
  EXPECT_NE(next_line("repacked "), "") << log_;
  EXPECT_EQ(context_.find("(unchanged since the last pack: kept)"), std::string::npos) << context_;
  EXPECT_EQ(pipelines(), std::vector<std::string>{"Two"});
  EXPECT_EQ(archive(), fresh_pack("-s ."));
  finish();
}

// A shader given by a link is watched where the link leads, after every pack: pointed at another file, the
// repack reads that file, and edits of that file (not of the link) repack from then on.
TEST_F(Watch, AShaderLinkIsFollowedWhereverItIsPointed) {
  write_file(dir_ / "v1" / "cs.comp", shader(kShaderMark + 1));
  write_file(dir_ / "v2" / "cs.comp", shader(kShaderMark + 2));
  write_file(dir_ / "v1" / "inc" / "common.glsl", include(kIncludeMark));
  write_file(dir_ / "v2" / "inc" / "common.glsl", include(kIncludeMark));
  fs::remove(dir_ / "cs.comp");
  fs::create_symlink(fs::path("v1") / "cs.comp", dir_ / "cs.comp");
  ASSERT_NO_FATAL_FAILURE(start({"--watch-quiet-ms", "50"}, false));
  EXPECT_TRUE(archive_has(kShaderMark + 1));
  fs::create_symlink(fs::path("v2") / "cs.comp", dir_ / "cs.comp.new");
  fs::rename(dir_ / "cs.comp.new", dir_ / "cs.comp");
  EXPECT_NE(next_line("repacked "), "") << log_;
  EXPECT_TRUE(archive_has(kShaderMark + 2));
  write_file(dir_ / "v2" / "cs.comp", shader(kShaderMark + 3));
  EXPECT_NE(next_line("repacked "), "") << log_;
  EXPECT_TRUE(archive_has(kShaderMark + 3));
  EXPECT_EQ(archive(), fresh_pack());
  finish();
}

TEST_F(Watch, SyntaxErrorsKeepTheArchiveAndTheirFixRepacks) {
  ASSERT_NO_FATAL_FAILURE(start());
  // A shader's syntax error: the error with its file and line, the archive untouched.
  write_file(dir_ / "cs.comp", shader(kShaderMark + 1, "", "data.v[2] = ;"));
  const std::string failed = next_line("pack failed ");
  EXPECT_TRUE(failed.ends_with(" (changed: cs.comp); keeping the last archive")) << log_;
  EXPECT_TRUE(std::regex_search(context_, std::regex(R"(cs\.comp:\d+: error: )"))) << context_;
  EXPECT_EQ(archive(), first_archive_);
  write_file(dir_ / "cs.comp", shader(kShaderMark + 2));
  EXPECT_NE(next_line("repacked "), "") << log_;
  EXPECT_TRUE(archive_has(kShaderMark + 2));
  const std::string good = archive();
  // The notation's: it reads no shader, yet the shaders stay watched (an edit of one is seen while the
  // notation is broken), and its fix repacks with the shader's latest text.
  write_file(dir_ / "a.json",
             "{\n  \"Pipelines\": [\n    " + compute_pipeline("P", "cs.comp") + ",,\n  ]\n}\n");
  EXPECT_NE(next_line("pack failed "), "") << log_;
  EXPECT_TRUE(std::regex_search(context_, std::regex(R"(a\.json:3:\d+: )"))) << context_;
  EXPECT_EQ(archive(), good);
  write_file(dir_ / "cs.comp", shader(kShaderMark + 3));
  EXPECT_NE(next_line("pack failed "), "") << log_;
  EXPECT_EQ(archive(), good);
  write_file(dir_ / "a.json", notation({compute_pipeline("P", "cs.comp")}));
  EXPECT_NE(next_line("repacked "), "") << log_;
  EXPECT_TRUE(archive_has(kShaderMark + 3));
  EXPECT_EQ(archive(), fresh_pack());
  finish();
}

TEST_F(Watch, IncludeChangesRepackAndANewIncludeIsWatched) {
  ASSERT_NO_FATAL_FAILURE(start());
  write_file(dir_ / "inc" / "common.glsl", include(kIncludeMark + 1));
  EXPECT_NE(next_line("repacked ").find("(changed: inc/common.glsl)"), std::string::npos) << log_;
  EXPECT_TRUE(archive_has(kIncludeMark + 1));
  EXPECT_FALSE(archive_has(kIncludeMark));
  // A new #include, in a directory no file of the last pack was in.
  write_file(dir_ / "extra" / "more.glsl", include(0x5EED3000, "kMore"));
  write_file(dir_ / "cs.comp", shader(kShaderMark, "#include \"extra/more.glsl\"\n", "data.v[3] = kMore;"));
  EXPECT_NE(next_line("repacked "), "") << log_;
  EXPECT_TRUE(archive_has(0x5EED3000));
  write_file(dir_ / "extra" / "more.glsl", include(0x5EED3001, "kMore"));
  EXPECT_NE(next_line("repacked ").find("(changed: extra/more.glsl)"), std::string::npos) << log_;
  EXPECT_TRUE(archive_has(0x5EED3001));
  EXPECT_EQ(archive(), fresh_pack());
  finish();
}

TEST_F(Watch, NotationEditsRenameAddAndRemovePipelines) {
  ASSERT_NO_FATAL_FAILURE(start());
  EXPECT_EQ(pipelines(), std::vector<std::string>{"P"});
  write_file(dir_ / "a.json", notation({compute_pipeline("Renamed", "cs.comp")}));
  EXPECT_NE(next_line("repacked ").find("(changed: a.json)"), std::string::npos) << log_;
  EXPECT_EQ(pipelines(), std::vector<std::string>{"Renamed"});
  // A pipeline with a shader of its own: the shader is watched from this pack on.
  write_file(dir_ / "q.comp", shader(0x5EED4000));
  write_file(dir_ / "a.json",
             notation({compute_pipeline("Renamed", "cs.comp"), compute_pipeline("Q", "q.comp")}));
  EXPECT_NE(next_line("repacked "), "") << log_;
  EXPECT_EQ(pipelines(), (std::vector<std::string>{"Q", "Renamed"}));  // the archive's order: by name
  write_file(dir_ / "q.comp", shader(0x5EED4001));
  EXPECT_NE(next_line("repacked ").find("(changed: q.comp)"), std::string::npos) << log_;
  EXPECT_TRUE(archive_has(0x5EED4001));
  write_file(dir_ / "a.json", notation({compute_pipeline("Q", "q.comp")}));
  EXPECT_NE(next_line("repacked "), "") << log_;
  EXPECT_EQ(pipelines(), std::vector<std::string>{"Q"});
  EXPECT_FALSE(archive_has(kShaderMark));
  EXPECT_EQ(archive(), fresh_pack());
  finish();
}

TEST_F(Watch, ADeletedShaderFailsAndItsReturnRepacks) {
  ASSERT_NO_FATAL_FAILURE(start());
  fs::remove(dir_ / "cs.comp");
  const std::string failed = next_line("pack failed ");
  EXPECT_NE(failed.find("(changed: cs.comp (gone)); keeping the last archive"), std::string::npos) << log_;
  EXPECT_NE(context_.find("cs.comp' not found"), std::string::npos) << context_;
  EXPECT_EQ(archive(), first_archive_);
  write_file(dir_ / "cs.comp", shader(kShaderMark + 5));
  EXPECT_NE(next_line("repacked ").find("(changed: cs.comp)"), std::string::npos) << log_;
  EXPECT_TRUE(archive_has(kShaderMark + 5));
  finish();
}

TEST_F(Watch, SavesByRenameByTruncationAndByDeleteAndCreateAreSeen) {
  ASSERT_NO_FATAL_FAILURE(start());
  save_by_rename(dir_ / "cs.comp", shader(kShaderMark + 1));
  EXPECT_NE(next_line("repacked ").find("(changed: cs.comp)"), std::string::npos) << log_;
  EXPECT_TRUE(archive_has(kShaderMark + 1));
  save_by_rename(dir_ / "inc" / "common.glsl", include(kIncludeMark + 1));
  EXPECT_NE(next_line("repacked ").find("(changed: inc/common.glsl)"), std::string::npos) << log_;
  EXPECT_TRUE(archive_has(kIncludeMark + 1));
  // Truncated, then written in two pieces a moment apart: one repack, of the whole text.
  {
    const std::string text = shader(kShaderMark + 2);
    std::ofstream file(dir_ / "cs.comp", std::ios::binary | std::ios::trunc);
    file << text.substr(0, 40) << std::flush;
    sleep_ms(10);
    file << text.substr(40);
  }
  EXPECT_NE(next_line("repacked "), "") << log_;
  EXPECT_TRUE(archive_has(kShaderMark + 2));
  fs::remove(dir_ / "cs.comp");
  write_file(dir_ / "cs.comp", shader(kShaderMark + 3));
  EXPECT_NE(next_line("repacked "), "") << log_;
  EXPECT_TRUE(archive_has(kShaderMark + 3));
  EXPECT_EQ(archive(), fresh_pack());
  finish();
}

TEST_F(Watch, ABurstOfSavesIsAtMostTwoRepacks) {
  ASSERT_NO_FATAL_FAILURE(start({}));  // the default quiet period
  for (uint32_t i = 1; i <= 20; ++i) {
    if (i % 2)
      write_file(dir_ / "cs.comp", shader(kShaderMark + i));
    else
      save_by_rename(dir_ / "cs.comp", shader(kShaderMark + i));
    sleep_ms(5);
  }
  EXPECT_NE(next_line("repacked "), "") << log_;
  EXPECT_TRUE(archive_gets(kShaderMark + 20));
  sleep_ms(600);  // any further repack of the burst would have come by now
  read_some(0);
  EXPECT_LE(count("repacked ") + count("pack failed "), 2u) << log_;
  EXPECT_EQ(archive(), fresh_pack());
  finish();
}

TEST_F(Watch, ARemovedDirectoryIsReportedAndItsReturnRepacks) {
  ASSERT_NO_FATAL_FAILURE(start());
  fs::remove_all(dir_ / "inc");
  EXPECT_NE(next_line("pack failed "), "") << log_;
  EXPECT_NE(context_.find("the directory 'inc' of watched files is gone"), std::string::npos) << context_;
  EXPECT_EQ(archive(), first_archive_);
  sleep_ms(200);  // nothing spins or dies while it is away
  EXPECT_TRUE(alive());
  write_file(dir_ / "inc" / "common.glsl", include(kIncludeMark + 7));
  EXPECT_NE(next_line("statepack: --watch: the directory 'inc' is back; watching it again"), "") << log_;
  EXPECT_NE(next_line("repacked "), "") << log_;
  EXPECT_TRUE(archive_gets(kIncludeMark + 7)) << log_;
  // Watched again: an edit in it repacks.
  write_file(dir_ / "inc" / "common.glsl", include(kIncludeMark + 8));
  EXPECT_TRUE(archive_gets(kIncludeMark + 8)) << log_;
  finish();
}

TEST_F(Watch, SigintAndSigtermEndItCleanly) {
  ASSERT_NO_FATAL_FAILURE(start());
  // The archive and depfile it writes itself are no change.
  read_some(400);
  EXPECT_EQ(count("repacked "), 0u) << log_;
  finish();
  // A stop signal just after an edit (in the quiet period or the pack): exit 0, a whole archive.
  log_.clear(), cursor_ = 0;
  ASSERT_NO_FATAL_FAILURE(start({"--watch-quiet-ms", "0", "--depfile", "out.spk.d"}));
  write_file(dir_ / "cs.comp", shader(kShaderMark + 9));
  sleep_ms(5);
  EXPECT_EQ(stop(SIGTERM), 0) << log_;
  EXPECT_NE(log_.find("stopped by SIGTERM"), std::string::npos) << log_;
  expect_no_temporaries();
  EXPECT_EQ(run_command("'" STATEPACK_EXE "' inspect '" + (dir_ / "out.spk").string() + "'").exit_code, 0);
}

TEST(WatchUsage, CheckOrNoOutputIsAUsageError) {
  auto run = [](const std::string& args) { return run_command("'" STATEPACK_EXE "' " + args); };
  auto check = run("pack -i a.json --vulkan --watch --check");
  EXPECT_EQ(check.exit_code, 2);
  EXPECT_NE(check.output.find("--watch repacks the archive at -o whenever an input changes; --check writes "
                              "nothing"),
            std::string::npos)
      << check.output;
  auto no_output = run("pack -i a.json --vulkan --watch");
  EXPECT_EQ(no_output.exit_code, 2);
  EXPECT_NE(no_output.output.find("--watch needs -o"), std::string::npos) << no_output.output;
  auto quiet_alone = run("pack -i a.json -o out.spk --vulkan --watch-quiet-ms 10");
  EXPECT_EQ(quiet_alone.exit_code, 2);
  EXPECT_NE(quiet_alone.output.find("--watch-quiet-ms is for --watch"), std::string::npos)
      << quiet_alone.output;
  auto help = run("pack --help");
  EXPECT_EQ(help.exit_code, 0);
  EXPECT_NE(help.output.find("--watch"), std::string::npos);
  EXPECT_NE(help.output.find("--watch-quiet-ms"), std::string::npos);
}

}  // namespace
