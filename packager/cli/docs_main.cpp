// statepack_docs: writes the parts of the documentation that come from the reader's own tables, and
// checks that the committed ones still match (a ctest), so the docs cannot drift from the code.
//   statepack_docs markdown          the enum reference, to stdout
//   statepack_docs check FILE        exit 1 when FILE's generated section differs, saying how to fix it
//   statepack_docs update FILE       rewrites FILE's generated section
#include <iostream>
#include <string>

#include "notation/input_file.hpp"
#include "notation/notation_reference.hpp"
#include "support/file_io.hpp"
#include "support/printable.hpp"

namespace {

using namespace statepack::packager;
using statepack::detail::printable;

constexpr const char* kRegenerate = "cmake --build build --target update_notation_docs";

// The document, read as every input of the project is (bounded, never blocking); the error names it.
bool read(const std::string& path, std::string& text, std::string& error) {
  InputText input = read_input_file(path, path, uint64_t(16) << 20);
  if (!input.error.empty()) return error = input.error, false;
  text = std::move(input.text);
  return true;
}

// The first line where `a` and `b` differ, 1-based, for the failure message.
size_t first_difference(const std::string& a, const std::string& b) {
  size_t line = 1;
  for (size_t i = 0; i < a.size() && i < b.size() && a[i] == b[i]; ++i)
    if (a[i] == '\n') ++line;
  return line;
}

}  // namespace

int main(int argc, char** argv) {
  const std::string command = argc > 1 ? argv[1] : "";
  const std::string markdown = enum_reference_markdown(enum_reference());
  if (command == "markdown" && argc == 2) {
    std::cout << markdown;
    return 0;
  }
  if ((command != "check" && command != "update") || argc != 3) {
    std::cerr << "usage: statepack_docs markdown | check FILE | update FILE\n";
    return 2;
  }
  const std::string path = argv[2];
  std::string document, error;
  if (!read(path, document, error)) {
    std::cerr << "statepack_docs: error: " << printable(error) << '\n';
    return 2;
  }
  auto updated = with_generated_section(document, markdown);
  if (!updated) {
    std::cerr << printable(path) << ": error: no generated section (a line '" << kGeneratedBegin
              << "', later a line '" << kGeneratedEnd << "')\n";
    return 1;
  }
  if (command == "check") {
    if (*updated == document) return 0;
    std::cerr << printable(path) << ":" << first_difference(document, *updated)
              << ": error: the enum reference differs from the reader's tables "
                 "(packager/notation/enum_tables.hpp); "
                 "regenerate it with: "
              << kRegenerate << '\n';
    return 1;
  }
  // Rewritten in place, atomically (a failed write leaves the old document), never through a link.
  if (*updated != document)
    if (auto written = statepack::detail::write_file_atomically(
            path, {reinterpret_cast<const uint8_t*>(updated->data()), updated->size()});
        !written) {
      std::cerr << "statepack_docs: error: " << printable(written.error().message) << '\n';
      return 1;
    }
  return 0;
}
