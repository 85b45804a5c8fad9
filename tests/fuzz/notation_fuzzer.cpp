// libFuzzer target for the notation reader: any bytes must become diagnostics, never a crash, a hang,
// an uncaught exception or unbounded memory. The input is split at NUL bytes into a small in-memory
// file set: the main document, then files it may import ("a.json", "b.json", "sub/c.json" through the
// -r directory "sub") and a shader file ("s.comp") that FilePath may name. Built with clang
// (-fsanitize=fuzzer,address,undefined) by tests/CMakeLists.txt and run for a bounded time by the test
// `fuzz.notation_reader`, seeded with every notation file of the repository.
#include <map>
#include <sstream>
#include <string>

#include "notation/notation.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace statepack::packager;
  static const char* const kNames[] = {"/m/main.json", "/m/a.json", "/m/b.json", "/m/sub/c.json"};
  std::map<std::string, std::string> files;
  std::string_view input(reinterpret_cast<const char*>(data), size);
  for (const char* name : kNames) {
    size_t end = input.find('\0');
    files[name] = std::string(input.substr(0, end));
    if (end == std::string_view::npos) break;
    input.remove_prefix(end + 1);
  }
  files["/m/s.comp"] = "#version 450\nvoid main() {}\n";

  NotationOptions options;
  options.memory_files = &files;
  options.render_state_dirs = {"/m/sub"};
  options.shader_dirs = {"/m/sub"};
  Diagnostics diagnostics(20);
  Notation notation;
  read_notation("/m/main.json", options, notation, diagnostics);
  resolve_references(notation, diagnostics);
  std::ostringstream printed;
  diagnostics.print(printed);
  return 0;
}
