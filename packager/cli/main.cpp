// statepack: the offline render-state packager CLI.
#include <CLI/CLI.hpp>

#include <filesystem>
#include <iostream>
#include <set>

#include "format/archive_format.hpp"
#include "inspect.hpp"
#include "merge.hpp"
#include "notation/notation_schema.hpp"
#include "pack/packer.hpp"
#include "verify.hpp"
#include "version.hpp"

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

std::optional<uint32_t> parse_vulkan_version(const std::string& text) {
  if (text == "1.0") return (1u << 22) | (0u << 12);
  if (text == "1.1") return (1u << 22) | (1u << 12);
  if (text == "1.2") return (1u << 22) | (2u << 12);
  if (text == "1.3") return (1u << 22) | (3u << 12);
  return std::nullopt;
}

}  // namespace

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

  PackOptions options;
  std::vector<std::string> inputs, render_state_dirs, shader_dirs, defines;
  std::string output, vulkan_version = "1.0", depfile, dump_dir, optimize = "none";
  bool strip_debug = false;
  bool vulkan = false, opengl = false, opengles = false, dx11 = false, dx12 = false, metal_macos = false,
       metal_ios = false, webgpu = false;
  CLI::App* pack = app.add_subcommand("pack", "Pack notation files into an archive (the default command)");
  pack->add_option("-i,--input", inputs,
                   "Input notation file (repeatable); searched in the CWD, then -r dirs")
      ->required();
  pack->add_option("-r,--render_state_dir", render_state_dirs,
                   "Directory to search for notation files (repeatable)");
  pack->add_option(
      "-s,--shader_dir", shader_dirs,
      "Directory to search for shader files and #includes after the referring file's own (repeatable)");
  auto* output_option = pack->add_option("-o,--output", output, "Output archive (required unless --check)");
  pack->add_flag("--check", options.check_only,
                 "Pack and validate everything, but write no archive or depfile (-o not needed)");
  pack->add_option("--max-errors", options.max_errors, "Stop after this many errors; 0: no limit")
      ->capture_default_str();
  pack->add_option("-t,--thread", options.threads, "Compiler threads (0: all cores)")->capture_default_str();
  pack->add_option("-v,--content_version", options.content_version,
                   "User content version stored in the header")
      ->capture_default_str();
  pack->add_option("-D", defines, "Macro for every shader, NAME=VALUE or NAME (repeatable)");
  pack->add_option("--depfile", depfile,
                   "Write a Make-style depfile listing every JSON and shader file read");
  pack->add_option("--vulkan_version", vulkan_version,
                   "Target Vulkan version: 1.0 (SPIR-V 1.0), 1.1, 1.2 or 1.3")
      ->capture_default_str();
  pack->add_option(
      "-d,--dump_dir", dump_dir,
      "Write each pipeline's final SPIR-V and its disassembly under DIR/Vulkan/<kind>/<pipeline>/");
  pack->add_option("--optimize", optimize, "SPIR-V optimisation: none, speed or size")->capture_default_str();
  pack->add_flag("--strip_debug,--strip_reflection", strip_debug,
                 "Strip debug information (names, lines) from the SPIR-V; binding names stay in the archive");
  pack->add_flag("--print_contents", options.print_contents, "Print the archive's contents");
  pack->add_flag("--vulkan", vulkan, "Produce the Vulkan backend (SPIR-V)");
  pack->add_flag(
      "--opengl", opengl,
      "Produce the OpenGL backend: GLSL compiled again for OpenGL 4.5 with GL_ARB_gl_spirv (GL_SPIRV "
      "defined, VULKAN not), bindings numbered per kind");
  pack->add_flag("--opengles", opengles, "OpenGL ES backend (not produced: warning)");
  pack->add_flag("--dx11", dx11, "Direct3D 11 backend (not produced on this platform: warning)");
  pack->add_flag("--dx12", dx12, "Direct3D 12 backend (not produced on this platform: warning)");
  pack->add_flag("--metal_macos", metal_macos,
                 "Metal macOS backend (not produced on this platform: warning)");
  pack->add_flag("--metal_ios", metal_ios, "Metal iOS backend (not produced on this platform: warning)");
  pack->add_flag("--webgpu", webgpu, "WebGPU backend (not produced: warning)");

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

  MergeOptions merge_options;
  std::vector<std::string> merge_inputs;
  std::string merge_output;
  CLI::App* merge = app.add_subcommand(
      "merge",
      "Merge archives into one: shared SPIR-V, shaders and layouts stored once; a name defined "
      "differently in two inputs is an error");
  merge->add_option("archives", merge_inputs, "Archives to merge, in order")->required();
  merge->add_option("-o,--output", merge_output, "The merged archive")->required();
  merge->add_option("-v,--content_version", merge_options.content_version,
                    "Content version of the merged archive (default: the inputs', which must then agree)");

  VerifyOptions verify_options;
  std::vector<std::string> verify_paths;
  std::string verify_format = "RGBA8_UNORM", verify_cache;
  bool verify_no_validation = false;
  CLI::App* verify = app.add_subcommand(
      "verify",
      "Unpack every object of archives on a local Vulkan device, validation layer on; exit 1 on any "
      "error or validation message");
  verify->add_option("archives", verify_paths, "Archives to verify")->required();
  verify->add_option(
      "--device", verify_options.device_index,
      "Vulkan device index (vkEnumeratePhysicalDevices order; default: the first Vulkan 1.3 one)");
  verify
      ->add_option("--format", verify_format,
                   "Format for render targets the archive leaves UNKNOWN (patched at run time)")
      ->capture_default_str();
  verify->add_option(
      "--cache", verify_cache,
      "Pipeline cache file: loaded when present and valid for this device, saved after (warming)");
  verify->add_flag("--no-validation", verify_no_validation, "Do not enable the validation layer");

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
  if (merge->parsed()) {
    for (const auto& p : merge_inputs) merge_options.inputs.emplace_back(p);
    merge_options.output = merge_output;
    return run_merge(merge_options, std::cout, std::cerr);
  }
  if (verify->parsed()) {
    for (const auto& p : verify_paths) verify_options.archives.emplace_back(p);
    auto format = parse_vk_format(verify_format);
    if (!format) {
      std::cerr << "statepack: error: --format: unknown texture format '" << printable(verify_format)
                << "' (use the notation's names, e.g. RGBA8_UNORM or BGRA8_UNORM_SRGB)\n";
      return kExitUsage;
    }
    verify_options.color_format = *format;
    verify_options.validation = !verify_no_validation;
    if (!verify_cache.empty()) verify_options.cache = verify_cache;
    return run_verify(verify_options, std::cout, std::cerr);
  }
  if (output_option->count() == 0 && !options.check_only) {
    std::cerr << "statepack: error: --output is required (or --check to write nothing)\n";
    return kExitUsage;
  }
  if (options.check_only && (output_option->count() > 0 || !depfile.empty())) {
    std::cerr << "statepack: error: --check writes nothing: drop -o and --depfile, or drop --check\n";
    return kExitUsage;
  }

  for (auto [on, flag] : {std::pair{opengles, "--opengles"},
                          {dx11, "--dx11"},
                          {dx12, "--dx12"},
                          {metal_macos, "--metal_macos"},
                          {metal_ios, "--metal_ios"},
                          {webgpu, "--webgpu"}})
    if (on)
      std::cerr << "statepack: warning: " << flag
                << ": this backend cannot be produced by statepack; ignored\n";
  if (!vulkan && !opengl) {
    std::cerr << "statepack: error: no backend to produce; pass --vulkan, --opengl or both\n";
    return kExitUsage;
  }
  options.vulkan = vulkan;
  options.opengl = opengl;
  auto version = parse_vulkan_version(vulkan_version);
  if (!version) {
    std::cerr << "statepack: error: --vulkan_version must be 1.0, 1.1, 1.2 or 1.3, not '" << vulkan_version
              << "'\n";
    return kExitUsage;
  }
  options.compile.vulkan_version = *version;
  const bool dirs_ok = check_search_dirs("-s", shader_dirs, std::cerr);
  if (!check_search_dirs("-r", render_state_dirs, std::cerr) || !dirs_ok) return kExitUsage;
  for (auto& i : inputs) options.inputs.emplace_back(i);
  for (auto& d : render_state_dirs) options.notation.render_state_dirs.emplace_back(d);
  for (auto& d : shader_dirs) {
    options.notation.shader_dirs.emplace_back(d);
    options.compile.include_dirs.emplace_back(d);
  }
  for (auto& d : defines) options.compile.global_macros.push_back(parse_define(d));
  options.output = output;
  if (!dump_dir.empty()) options.dump_dir = dump_dir;
  options.compile.strip_debug_info = strip_debug;
  if (optimize == "speed")
    options.compile.optimization = Optimization::speed;
  else if (optimize == "size")
    options.compile.optimization = Optimization::size;
  else if (optimize != "none") {
    std::cerr << "statepack: error: --optimize must be none, speed or size, not '" << optimize << "'\n";
    return kExitUsage;
  }
  if (!depfile.empty()) options.depfile = depfile;
  return run_pack(options, std::cout, std::cerr);
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
