// statepack: the offline render-state packager CLI.
#include <CLI/CLI.hpp>

#include <algorithm>
#include <filesystem>
#include <iostream>
#include <set>
#include <sstream>
#include <thread>

#include "format/archive_format.hpp"
#include "huge_pages.hpp"
#include "inspect.hpp"
#include "merge.hpp"
#include "notation/notation_schema.hpp"
#include "pack/packer.hpp"
#include "pack/phase_times.hpp"
#include "shaders/compile_cache.hpp"
#include "verify.hpp"
#include "version.hpp"
#include "watch.hpp"

namespace {

using namespace statepack::packager;

// "NAME=VALUE" or "NAME" (defined as 1), as -D does for C compilers.
std::pair<std::string, std::string> parse_define(const std::string& text) {
  auto eq = text.find('=');
  if (eq == std::string::npos) return {text, "1"};
  return {text.substr(0, eq), text.substr(eq + 1)};
}

// A -s or -r directory that is not there would fail every lookup in it, each with its own "not found"
// error; one error naming the directory says what is wrong. Each directory is reported once.
bool check_search_dirs(const char* option, const std::vector<std::string>& dirs, std::ostream& err) {
  bool ok = true;
  std::set<std::string> reported;
  for (const auto& dir : dirs) {
    std::error_code ec;
    auto status = std::filesystem::status(dir, ec);
    if (std::filesystem::is_directory(status) || !reported.insert(dir).second) continue;
    std::string reason = status.type() == std::filesystem::file_type::not_found ? "does not exist"
                         : ec ? "cannot be examined: " + ec.message()
                              : "is not a directory";
    err << "statepack: error: " << option << " '" << printable(display_path(dir)) << "': the directory "
        << reason << '\n';
    ok = false;
  }
  return ok;
}

// A count, size, index or version option refuses a negative number by its sign: CLI11 converts "-1"
// to some unsigned types as its two's complement (a limit of 2^64-1) and AsSizeValue reads it as a size,
// and a negative --device would mean "the default". A transform runs before the option's other
// validators and transforms, so this sees the text as the user wrote it.
CLI::Option* not_negative(CLI::Option* option) {
  return option->transform(CLI::Validator(
      [](std::string& text) -> std::string {
        const auto first = text.find_first_not_of(" \t");
        if (first != std::string::npos && text[first] == '-') return "must not be negative, not " + text;
        return {};
      },
      ""));
}

std::optional<uint32_t> parse_vulkan_version(const std::string& text) {
  if (text == "1.0") return (1u << 22) | (0u << 12);
  if (text == "1.1") return (1u << 22) | (1u << 12);
  if (text == "1.2") return (1u << 22) | (2u << 12);
  if (text == "1.3") return (1u << 22) | (3u << 12);
  return std::nullopt;
}

}  // namespace

// `pack`: its options, and the checks that turn them into PackOptions.
struct PackCommand {
  CLI::App* app = nullptr;
  CLI::Option* output_option = nullptr;
  CLI::Option* quiet_option = nullptr;
  PackOptions options;
  bool watch = false, list_inputs = false;
  WatchOptions watch_options;
  std::vector<std::string> inputs, render_state_dirs, shader_dirs, defines;
  std::string output, vulkan_version = "1.0", depfile, dump_dir, optimize = "none", cache_dir,
                      shader_environment = "diligent", shard;
  std::optional<std::string> remote_cache;
  bool strip_debug = false;
  uint64_t max_input_size = kMaxInputBytes;
  bool vulkan = false, opengl = false, opengles = false, dx11 = false, dx12 = false, metal_macos = false,
       metal_ios = false, webgpu = false;

  void add_to(CLI::App& parent) {
    app = parent.add_subcommand("pack", "Pack notation files into an archive (the default command)");
    app->add_option("-i,--input", inputs,
                    "Input notation file (repeatable); searched in the CWD, then -r dirs")
        ->required();
    app->add_option("-r,--render_state_dir", render_state_dirs,
                    "Directory to search for notation files (repeatable)");
    app->add_option(
        "-s,--shader_dir", shader_dirs,
        "Directory to search for shader files and #includes after the referring file's own (repeatable)");
    output_option = app->add_option("-o,--output", output, "Output archive (required unless --check)");
    app->add_flag("--check", options.check_only,
                  "Pack and validate everything, but write no archive or depfile (-o not needed)");
    app->add_flag("--watch", watch,
                  "Pack, then stay resident and repack whenever a file the pack read (notation, import, "
                  "shader, #include) is written, created, renamed over or deleted; one line per repack. A "
                  "failed repack prints its errors and keeps the last archive. Ctrl-C ends it. Needs -o");
    quiet_option =
        not_negative(app->add_option("--watch-quiet-ms", watch_options.quiet_ms,
                                     "--watch: milliseconds without another change before a repack (a burst "
                                     "of saves is one repack)"))
            ->capture_default_str();
    not_negative(
        app->add_option("--max-errors", options.max_errors, "Stop after this many errors; 0: no limit"))
        ->capture_default_str();
    // One limit for every file read (notation files, shaders, includes) and for a shader's includes in
    // all: a bound on memory, not on what a project may hold.
    app->add_option("--max-input-size", max_input_size,
                    "Largest notation file, shader or #include expansion to read, in bytes (suffixes K, M, G "
                    "for KiB, MiB, GiB)")
        ->capture_default_str()
        ->transform(CLI::AsSizeValue(false))
        ->check(CLI::Range(uint64_t{1}, uint64_t{1} << 40));
    not_negative(app->get_option("--max-input-size"));
    not_negative(app->add_option("-t,--thread", options.threads, "Compiler threads (0: all cores)"))
        ->capture_default_str();
    not_negative(app->add_option("-v,--content_version", options.content_version,
                                 "User content version stored in the header"))
        ->capture_default_str();
    app->add_option("-D", defines, "Macro for every shader, NAME=VALUE or NAME (repeatable)");
    app->add_option("--depfile", depfile,
                    "Write a Make-style depfile listing every JSON and shader file read");
    app->add_option("--vulkan_version", vulkan_version,
                    "Target Vulkan version: 1.0 (SPIR-V 1.0), 1.1, 1.2 or 1.3")
        ->capture_default_str();
    app->add_option(
        "-d,--dump_dir", dump_dir,
        "Write each pipeline's final SPIR-V and its disassembly under DIR/Vulkan/<kind>/<pipeline>/");
    app->add_option("--optimize", optimize, "SPIR-V optimisation: none, speed or size")
        ->capture_default_str();
    app->add_option("--shader-environment", shader_environment,
                    "What every shader is compiled with besides its own macros: diligent (Diligent's "
                    "definitions and its compiler, backend and stage macros, as Diligent compiles shaders) "
                    "or none")
        ->capture_default_str();
    app->add_flag(
        "--strip_debug,--strip_reflection", strip_debug,
        "Strip debug information (names, lines) from the SPIR-V; binding names stay in the archive");
    app->add_flag("--strict", options.strict,
                  "Make errors of what Diligent only warns about: ResourceLayout variables and immutable "
                  "samplers that name nothing the shaders use");
    app->add_flag("--print_contents", options.print_contents, "Print the archive's contents");
    app->add_flag("--time-report", options.time_report,
                  "Print the wall time of each stage of the pack (and the compile cache's hits)");
    app->add_option("--cache-dir", cache_dir,
                    "Keep compiled and finalised SPIR-V in DIR between runs: an unchanged shader (its text, "
                    "#includes, macros and options) is not compiled again; the archive is the same bytes");
    app->add_option("--cache-max-size", options.cache_max_bytes,
                    "Size bound of --cache-dir, least recently used entries removed first (suffixes K, M, G)")
        ->capture_default_str()
        ->transform(CLI::AsSizeValue(false));
    not_negative(app->get_option("--cache-max-size"));
    app->add_option("--remote-cache", remote_cache,
                    "Servers behind the compile cache, ccache's remote_storage syntax: 'URL[|attr...] ...' "
                    "with http://, redis:// or file: URLs (docs/cli.md \"Teams and CI\"); default: "
                    "$STATEPACK_REMOTE_CACHE; --remote-cache= for none. Entries are signed with "
                    "$STATEPACK_CACHE_KEY (or the file $STATEPACK_CACHE_KEY_FILE names) when set, and "
                    "unsigned ones refused")
        ->expected(0, 1);
    app->add_option(
        "--shard", shard,
        "K/N: compile only the shaders whose compile key falls in shard K of N (1 <= K <= N) into "
        "the caches, and write no archive (a CI matrix job; then pack with --no-compile)");
    app->add_flag("--list-inputs", list_inputs,
                  "Print every file the pack read (notation files, imports, shaders, #includes), one per "
                  "line, relative to the working directory when below it; with --check, the inputs a "
                  "hermetic build declares");
    app->add_flag("--no-compile", options.compile.no_compile,
                  "Assemble the archive from the caches (local and remote): a shader they do not have is an "
                  "error naming it, not a compile");
    app->add_flag_callback(
        "--no-archive-reuse", [this] { options.archive_reuse = false; },
        "With a cache: make the archive again even when nothing changed since the pack "
        "that recorded it (its record is neither read nor written; shaders still come "
        "from the cache)");
    app->add_flag("--vulkan", vulkan, "Produce the Vulkan backend (SPIR-V)");
    app->add_flag("--opengl", opengl,
                  "Produce the OpenGL backend (OpenGL 4.5 + GL_ARB_gl_spirv) from the same sources: each "
                  "shader's Vulkan SPIR-V translated (SPIRV-Cross, then glslang's OpenGL client); GLSL that "
                  "tests VULKAN or GL_SPIRV is compiled from its own text");
    app->add_flag("--opengles", opengles, "OpenGL ES backend (not produced: warning)");
    app->add_flag("--dx11", dx11, "Direct3D 11 backend (not produced on this platform: warning)");
    app->add_flag("--dx12", dx12, "Direct3D 12 backend (not produced on this platform: warning)");
    app->add_flag("--metal_macos", metal_macos,
                  "Metal macOS backend (not produced on this platform: warning)");
    app->add_flag("--metal_ios", metal_ios, "Metal iOS backend (not produced on this platform: warning)");
    app->add_flag("--webgpu", webgpu, "WebGPU backend (not produced: warning)");
  }

  // The shared cache's options and environment (--remote-cache, the team key, --shard, --no-compile).
  bool settle_cache(std::ostream& err) {
    const char* from_environment = std::getenv("STATEPACK_REMOTE_CACHE");
    const std::string remote = remote_cache ? *remote_cache : from_environment ? from_environment : "";
    if (remote.find_first_not_of(" \t\n") != std::string::npos) {
      std::string error;
      auto specs = parse_remote_storage(remote, error);
      if (!specs) {
        err << "statepack: error: " << (remote_cache ? "--remote-cache" : "STATEPACK_REMOTE_CACHE") << ": "
            << printable(error) << "\n";
        return false;
      }
      options.remote_cache = std::move(*specs);
    }
    if (!read_signing_key(err)) return false;
    const bool any_cache = !cache_dir.empty() || !options.remote_cache.empty();
    if (!shard.empty()) {
      unsigned k = 0, n = 0;
      char slash = 0, rest = 0;
      std::istringstream in(shard);
      if (!(in >> k >> slash >> n) || slash != '/' || in >> rest || k < 1 || k > n || n > 65536) {
        err << "statepack: error: --shard must be K/N with 1 <= K <= N <= 65536, not '" << printable(shard)
            << "'\n";
        return false;
      }
      options.shard = k, options.shards = n;
      if (output_option->count() > 0 || !depfile.empty() || options.check_only || watch) {
        err << "statepack: error: --shard compiles into the caches and writes no archive: drop -o, "
               "--depfile, --check and --watch\n";
        return false;
      }
    }
    if ((options.shards || options.compile.no_compile) && !any_cache) {
      err << "statepack: error: " << (options.shards ? "--shard" : "--no-compile")
          << " needs a compile cache: --cache-dir, --remote-cache or STATEPACK_REMOTE_CACHE\n";
      return false;
    }
    const bool any_writable =
        !cache_dir.empty() || std::any_of(options.remote_cache.begin(), options.remote_cache.end(),
                                          [](const RemoteSpec& r) { return !r.read_only; });
    if (options.shards && !any_writable) {
      err << "statepack: error: --shard compiles into the caches, and every one given is read-only: add "
             "--cache-dir or a server without read-only\n";
      return false;
    }
    if (options.shards && options.compile.no_compile) {
      err << "statepack: error: --shard compiles; --no-compile forbids it: drop one of them\n";
      return false;
    }
    return true;
  }

  // The team's key: STATEPACK_CACHE_KEY itself, or the file STATEPACK_CACHE_KEY_FILE names (never an
  // argument: a command line is visible to every user of the machine). A trailing newline is not part of it.
  bool read_signing_key(std::ostream& err) {
    std::string key;
    if (const char* text = std::getenv("STATEPACK_CACHE_KEY"); text && *text) {
      key = text;
    } else if (const char* file = std::getenv("STATEPACK_CACHE_KEY_FILE"); file && *file) {
      InputText input = read_input_file(file, file, 64 << 10);
      if (!input.error.empty()) {
        err << "statepack: error: STATEPACK_CACHE_KEY_FILE: " << printable(input.error) << "\n";
        return false;
      }
      key = std::move(input.text);
      while (!key.empty() && (key.back() == '\n' || key.back() == '\r')) key.pop_back();
      if (key.empty()) {
        err << "statepack: error: STATEPACK_CACHE_KEY_FILE: '" << printable(file) << "' holds no key\n";
        return false;
      }
    }
    options.cache_signing_key.assign(key.begin(), key.end());
    return true;
  }

  // Turns the options into `options`; false (with the error printed) for a usage error.
  bool settle(std::ostream& err) {
    if (watch && options.check_only) {
      err << "statepack: error: --watch repacks the archive at -o whenever an input changes; --check writes "
             "nothing: drop one of them\n";
      return false;
    }
    if (watch && list_inputs) {
      err << "statepack: error: --list-inputs lists what one pack read; --watch repacks: drop one of them\n";
      return false;
    }
    if (watch && output_option->count() == 0) {
      err << "statepack: error: --watch needs -o: it repacks the archive there whenever an input changes\n";
      return false;
    }
    if (!watch && quiet_option->count() > 0) {
      err << "statepack: error: --watch-quiet-ms is for --watch\n";
      return false;
    }
    if (!settle_cache(err)) return false;
    if (output_option->count() == 0 && !options.check_only && !options.shards) {
      err << "statepack: error: --output is required (or --check to write nothing)\n";
      return false;
    }
    if (options.check_only && (output_option->count() > 0 || !depfile.empty())) {
      err << "statepack: error: --check writes nothing: drop -o and --depfile, or drop --check\n";
      return false;
    }
    for (auto [on, flag] : {std::pair{opengles, "--opengles"},
                            {dx11, "--dx11"},
                            {dx12, "--dx12"},
                            {metal_macos, "--metal_macos"},
                            {metal_ios, "--metal_ios"},
                            {webgpu, "--webgpu"}})
      if (on)
        err << "statepack: warning: " << flag << ": this backend cannot be produced by statepack; ignored\n";
    if (!vulkan && !opengl) {
      err << "statepack: error: no backend to produce; pass --vulkan, --opengl or both\n";
      return false;
    }
    options.vulkan = vulkan;
    options.opengl = opengl;
    auto version = parse_vulkan_version(vulkan_version);
    if (!version) {
      err << "statepack: error: --vulkan_version must be 1.0, 1.1, 1.2 or 1.3, not '"
          << printable(vulkan_version) << "'\n";
      return false;
    }
    options.compile.vulkan_version = *version;
    const bool dirs_ok = check_search_dirs("-s", shader_dirs, err);
    if (!check_search_dirs("-r", render_state_dirs, err) || !dirs_ok) return false;
    for (auto& i : inputs) options.inputs.emplace_back(i);
    for (auto& d : render_state_dirs) options.notation.render_state_dirs.emplace_back(d);
    for (auto& d : shader_dirs) {
      options.notation.shader_dirs.emplace_back(d);
      options.compile.include_dirs.emplace_back(d);
    }
    for (auto& d : defines) options.compile.global_macros.push_back(parse_define(d));
    options.notation.max_input_bytes = options.compile.max_input_bytes = max_input_size;
    options.output = output;
    if (!dump_dir.empty()) options.dump_dir = dump_dir;
    options.compile.strip_debug_info = strip_debug;
    if (optimize == "speed")
      options.compile.optimization = Optimization::speed;
    else if (optimize == "size")
      options.compile.optimization = Optimization::size;
    else if (optimize != "none") {
      err << "statepack: error: --optimize must be none, speed or size, not '" << printable(optimize)
          << "'\n";
      return false;
    }
    if (shader_environment != "diligent" && shader_environment != "none") {
      err << "statepack: error: --shader-environment must be diligent or none, not '"
          << printable(shader_environment) << "'\n";
      return false;
    }
    options.compile.shader_environment = shader_environment == "diligent";
    if (!depfile.empty()) options.depfile = depfile;
    if (!cache_dir.empty()) options.cache_dir = cache_dir;
    return true;
  }
};

// `cache prune`: trims a --cache-dir to a size.
struct CacheCommand {
  CLI::App* app = nullptr;
  CLI::App* prune = nullptr;
  CLI::App* export_command = nullptr;
  CLI::App* import_command = nullptr;
  std::string dir, file;
  uint64_t max_bytes = uint64_t(1) << 30;

  void add_to(CLI::App& parent) {
    app = parent.add_subcommand("cache", "Look after a compile cache directory (pack --cache-dir)");
    app->require_subcommand(1);
    prune = app->add_subcommand(
        "prune", "Remove the least recently used entries until the cache holds at most --max-size");
    prune->add_option("dir", dir, "The cache directory")->required();
    prune->add_option("--max-size", max_bytes, "Bytes to keep at most (suffixes K, M, G; 0 empties it)")
        ->capture_default_str()
        ->transform(CLI::AsSizeValue(false));
    not_negative(prune->get_option("--max-size"));
    export_command = app->add_subcommand(
        "export",
        "Write every entry of a cache directory into one file (a build artifact for another machine)");
    export_command->add_option("dir", dir, "The cache directory")->required();
    export_command->add_option("file", file, "The file to write ('-': standard output)")->required();
    import_command = app->add_subcommand(
        "import",
        "Add the entries of an exported file to a cache directory, each checked (and, with "
        "$STATEPACK_CACHE_KEY or $STATEPACK_CACHE_KEY_FILE, its signature) first");
    import_command->add_option("dir", dir, "The cache directory (created if missing)")->required();
    import_command->add_option("file", file, "The exported file")->required();
  }
  int run(const std::vector<uint8_t>& secret) {
    if (export_command->parsed() || import_command->parsed()) {
      const bool exporting = export_command->parsed();
      const auto r = exporting ? CompileCache::export_entries(dir, file)
                               : CompileCache::import_entries(dir, file, secret);
      if (!r.error.empty()) {
        std::cerr << "statepack: error: " << printable(r.error) << '\n';
        return r.exit_code;
      }
      (exporting && file == "-" ? std::cerr : std::cout)
          << printable(exporting ? file : dir) << ": " << r.entries << " entries, " << r.bytes << " bytes "
          << (exporting ? "exported" : "imported")
          << (exporting ? ""
                        : "; " + std::to_string(r.present) + " already present, " +
                              std::to_string(r.refused) + " refused")
          << '\n';
      return r.refused ? kExitInputError : kExitSuccess;
    }
    auto r = CompileCache::prune(dir, max_bytes);
    if (!r.error.empty()) {
      std::cerr << "statepack: error: " << r.error << '\n';
      return kExitUsage;
    }
    std::cout << printable(dir) << ": " << r.entries_before << " entries, " << r.bytes_before << " bytes -> "
              << r.entries_after << " entries, " << r.bytes_after << " bytes\n";
    return kExitSuccess;
  }
};

struct MergeCommand {
  CLI::App* app = nullptr;
  MergeOptions options;
  std::vector<std::string> inputs;
  std::string output;

  void add_to(CLI::App& parent) {
    app = parent.add_subcommand("merge",
                                "Merge archives into one: shared SPIR-V, shaders and layouts stored once; a "
                                "name defined differently in two inputs is an error");
    app->add_option("archives", inputs, "Archives to merge, in order")->required();
    app->add_option("-o,--output", output, "The merged archive")->required();
    not_negative(app->add_option(
        "-v,--content_version", options.content_version,
        "Content version of the merged archive (default: the inputs', which must then agree)"));
  }
  int run() {
    for (const auto& p : inputs) options.inputs.emplace_back(p);
    options.output = output;
    return run_merge(options, std::cout, std::cerr);
  }
};

struct VerifyCommand {
  CLI::App* app = nullptr;
  VerifyOptions options;
  std::vector<std::string> paths;
  std::string format = "RGBA8_UNORM", cache, variants, worker_start;
  bool no_validation = false;

  void add_to(CLI::App& parent) {
    app = parent.add_subcommand(
        "verify",
        "Unpack every object of archives on a local Vulkan device, validation layer on; "
        "exit 1 on any error or validation message");
    app->add_option("archives", paths, "Archives to verify")->required();
    not_negative(app->add_option(
        "--device", options.device_index,
        "Vulkan device index (vkEnumeratePhysicalDevices order; default: the first Vulkan 1.3 one)"));
    app->add_option(
           "--format", format,
           "Format for render targets the archive leaves to run time (UNKNOWN, or absent while the pixel "
           "shader writes them)")
        ->capture_default_str();
    app->add_option(
        "--cache", cache,
        "Pipeline cache file: loaded when present and valid for this device, saved after (warming)");
    app->add_option(
        "--variants", variants,
        "Variants file (Dearchiver::save_variants, docs/variants.md): create exactly these patched "
        "pipelines instead of every object; with --cache, warms the cache for them");
    app->add_flag("--no-validation", no_validation, "Do not enable the validation layer");
    not_negative(
        app->add_option("--timeout", options.timeout_seconds,
                        "Seconds an object may take to create: objects are created in worker processes, so a "
                        "driver crash or hang fails only that object (0: in this process, no limit)"))
        ->capture_default_str();
    // Internal: a worker of the above, started by verify itself (verify_supervisor.cpp).
    app->add_option("--worker-start", worker_start)->group("");
  }
  int run() {
    for (const auto& p : paths) options.archives.emplace_back(p);
    auto color_format = parse_vk_format(format);
    if (!color_format) {
      std::cerr << "statepack: error: --format: unknown texture format '" << printable(format)
                << "' (use the notation's names, e.g. RGBA8_UNORM or BGRA8_UNORM_SRGB)\n";
      return kExitUsage;
    }
    options.color_format = *color_format;
    options.validation = !no_validation;
    if (!cache.empty()) options.cache = cache;
    if (!variants.empty()) options.variants = variants;
    if (!worker_start.empty()) {
      VerifyOptions::Position start;
      char colon = 0;
      std::istringstream in(worker_start);
      if (!(in >> start.archive >> colon >> start.object) || colon != ':') {
        std::cerr << "statepack: error: --worker-start: expected ARCHIVE:OBJECT\n";
        return kExitUsage;
      }
      options.worker_start = start;
    }
    return run_verify(options, std::cout, std::cerr);
  }
};

// pack --list-inputs: the pack, then every file it read (also when it failed: what it managed to read).
int pack_and_list_inputs(const PackOptions& options) {
  PackSession session;
  const int code = run_pack(options, std::cout, std::cerr, &session);
  std::set<std::string> names;
  for (const auto& path : session.files_read) names.insert(display_path(path));
  for (const auto& name : names) std::cout << printable(name) << '\n';
  return code;
}

int run(int argc, char** argv) {
  // Diligent command lines have no subcommand: "statepack -i a.json ..." means "statepack pack -i a.json
  // ...".
  std::vector<std::string> args(argv, argv + argc);
  if (args.size() > 1 && args[1].starts_with("-") && args[1] != "-h" && args[1] != "--help" &&
      args[1] != "--version")
    args.insert(args.begin() + 1, "pack");

  CLI::App app{
      "statepack: packs render-state notation (DRSN JSON) and GLSL/HLSL shaders into one archive of\n"
      "pre-compiled SPIR-V that libstatepack_dearchiver turns into Vulkan pipelines."};
  app.set_version_flag("--version", std::string("statepack ") + kVersionString + " (archive format " +
                                        std::to_string(statepack::format::kWrittenVersion) + ", " +
                                        std::to_string(statepack::format::kFormatVersion) +
                                        " with OpenGL tessellation; reads 1 to " +
                                        std::to_string(statepack::format::kFormatVersion) + ")");
  app.require_subcommand(1);
  app.footer("Exit codes: 0 success, 1 input error (notation, shader), 2 usage error, 3 I/O error.");

  PackCommand pack;
  pack.add_to(app);
  std::string inspect_path;
  bool inspect_json = false;
  CLI::App* inspect =
      app.add_subcommand("inspect", "Print every object of an archive: sizes, layouts, bindings");
  inspect->add_option("archive", inspect_path, "The archive")->required();
  inspect->add_flag("--json", inspect_json, "Print JSON instead of text");
  CLI::App* schema_command = app.add_subcommand(
      "schema",
      "Print the notation's JSON Schema (draft-07), for editors: generated from the tables the "
      "packer reads with");
  MergeCommand merge;
  merge.add_to(app);
  CacheCommand cache;
  cache.add_to(app);
  VerifyCommand verify;
  verify.add_to(app);

  // CLI11's messages quote what was typed: escaped like every other name that reaches the terminal.
  app.failure_message([](const CLI::App*, const CLI::Error& e) {
    return printable(e.what()) + "\nRun with --help for more information.\n";
  });
  try {
    std::vector<char*> raw;
    for (auto& a : args) raw.push_back(a.data());
    app.parse(static_cast<int>(raw.size()), raw.data());
  } catch (const CLI::ParseError& e) {
    int code = app.exit(e);
    return code == 0 ? kExitSuccess : kExitUsage;
  }

  if (inspect->parsed()) return run_inspect(inspect_path, inspect_json, std::cout, std::cerr);
  if (schema_command->parsed()) {
    std::cout << schema::notation_json_schema().dump(2) << '\n';
    return kExitSuccess;
  }
  if (merge.app->parsed()) return merge.run();
  if (cache.app->parsed()) {  // (the team key is read for an import only)
    if (cache.import_command->parsed() && !pack.read_signing_key(std::cerr)) return kExitUsage;
    return cache.run(pack.options.cache_signing_key);
  }
  if (verify.app->parsed()) return verify.run();
  std::ostringstream settled;
  if (!pack.settle(settled)) {
    std::cerr << settled.str();
    return kExitUsage;
  }
  if (settled.str().empty() && !pack.watch && !pack.list_inputs)
    if (auto code = pack_if_unchanged(pack.options, std::cout, std::cerr)) return *code;
  // Not for --watch: a resident process keeps its heap on its own terms (watch.cpp).
  if (!pack.watch) {
    PhaseTimes times(pack.options.time_report ? &std::cerr : nullptr);
    const size_t heaps =
        use_huge_pages(pack.options.threads ? pack.options.threads : std::thread::hardware_concurrency());
    times.done("heaps on huge pages (" + std::to_string(heaps) + " advised)");
  }
  std::cerr << settled.str();
  if (pack.watch) return run_watch(pack.options, pack.watch_options, std::cout, std::cerr);
  if (pack.list_inputs) return pack_and_list_inputs(pack.options);
  return run_pack(pack.options, std::cout, std::cerr);
}

// No exception may end the process with an abort: every one becomes an error line and an exit code.
int main(int argc, char** argv) {
  try {
    return run(argc, argv);
  } catch (const std::bad_alloc&) {
    std::cerr << "statepack: error: out of memory\n";
    return kExitIoError;
  } catch (const std::exception& e) {
    std::cerr << "statepack: error: internal error: " << printable(e.what()) << '\n';
    return kExitInputError;
  }
}
