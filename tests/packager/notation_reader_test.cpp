// The notation reader in process, on in-memory files (NotationOptions::memory_files, the hook the
// notation fuzzer uses): imports, file-local defaults, name resolution and the placement of errors,
// without spawning the packager or touching the disk. The CLI tests cover the same reader end to end.
#include <gtest/gtest.h>

#include <map>
#include <string>

#include "notation/notation.hpp"

namespace statepack::packager {
namespace {

using Files = std::map<std::string, std::string>;

// Reads /p/main.json from `files` (paths under /p), shader files resolved against /p/shaders.
struct Read {
  std::map<std::string, std::string> files;  // memory_files is borrowed for the read
  Notation notation;
  Diagnostics diagnostics{0};
  explicit Read(Files in) : files(std::move(in)) {
    NotationOptions options;
    options.memory_files = &files;
    options.shader_dirs = {"/p/shaders"};
    read_notation("/p/main.json", options, notation, diagnostics);
    if (!diagnostics.has_errors()) resolve_references(notation, diagnostics);
  }
  std::vector<Diagnostic> all() const { return diagnostics.all(); }
};

const PipelineDesc* pipeline(const Notation& n, std::string_view name) {
  for (const auto& p : n.pipelines)
    if (p.name == name) return &p;
  return nullptr;
}

constexpr const char* kPipeline = R"({
  "PSODesc": { "Name": "%NAME%" },
  "GraphicsPipeline": { "RTVFormats": { "0": "RGBA8_UNORM" } },
  "pVS": { "Desc": { "Name": "VS" }, "FilePath": "screen.hlsl", "EntryPoint": "VSMain" },
  "pPS": { "Desc": { "Name": "PS" }, "FilePath": "shade.hlsl", "EntryPoint": "PSMain" }
})";

std::string pipeline_json(const std::string& name) {
  std::string s = kPipeline;
  s.replace(s.find("%NAME%"), 6, name);
  return s;
}

TEST(NotationReader, ImportedPipelinesAreReadAndDefaultsStayInTheirFile) {
  Read r(Files{
      {"/p/main.json", R"({ "Imports": ["lib/a.json"], "Pipelines": [)" + pipeline_json("Main PSO") + "] }"},
      {"/p/lib/a.json", R"({ "Defaults": { "Shader": { "SourceLanguage": "HLSL" },
                                           "Pipeline": { "GraphicsPipeline": { "RasterizerDesc": { "CullMode": "NONE" } } } },
                             "Pipelines": [)" +
                            pipeline_json("Imported PSO") + "] }"},
      {"/p/shaders/screen.hlsl", "float4 VSMain() : SV_Position { return 0; }"},
      {"/p/shaders/shade.hlsl", "float4 PSMain() : SV_Target { return 1; }"},
  });
  for (const auto& d : r.all()) ADD_FAILURE() << format_diagnostic(d);
  const PipelineDesc* main = pipeline(r.notation, "Main PSO");
  const PipelineDesc* imported = pipeline(r.notation, "Imported PSO");
  ASSERT_TRUE(main && imported);
  EXPECT_EQ(imported->graphics.cull_mode, 0u);  // a.json's default: NONE
  EXPECT_EQ(main->graphics.cull_mode, 2u);      // main.json has no defaults: BACK
  ASSERT_EQ(imported->shaders.size(), 2u);
  EXPECT_EQ(imported->shaders[0].language, SourceLanguage::hlsl);
  EXPECT_EQ(imported->shaders[0].file, std::filesystem::path("/p/shaders/screen.hlsl"));
  EXPECT_EQ(r.notation.files_read.size(), 2u);
}

// A cycle is a warning, as Diligent skips a file it is reading already: the import that closes it is
// skipped, and the chain is named at it.
TEST(NotationReader, AnImportCycleNamesItsChainAtTheImport) {
  Read r(Files{{"/p/main.json", R"({ "Imports": ["b.json"] })"},
               {"/p/b.json", "{\n  \"Imports\": [\"main.json\"]\n}"}});
  auto all = r.all();
  ASSERT_EQ(all.size(), 1u);
  EXPECT_EQ(all[0].severity, Diagnostic::Severity::warning);
  // In memory the chain names the paths as the file set does (the CLI names them as the user did).
  EXPECT_EQ(
      all[0].message,
      "import cycle: /p/main.json -> /p/b.json -> /p/main.json (the import is skipped: the file is being "
      "read already, as in Diligent)");
  EXPECT_EQ(all[0].where.line, 2);
  EXPECT_EQ(all[0].where.pointer, "/Imports/0");
}

TEST(NotationReader, UnknownKeysArePlacedWithTheirPointerAndASuggestion) {
  Read r(Files{{"/p/main.json", "{\n  \"Pipelines\": [\n    { \"PSODesc\": { \"Nmae\": \"X\" } }\n  ]\n}"}});
  bool found = false;
  for (const auto& d : r.all()) {
    if (d.message.find("'Nmae'") == std::string::npos) continue;
    found = true;
    EXPECT_NE(d.message.find("did you mean 'Name'?"), std::string::npos) << d.message;
    EXPECT_EQ(d.where.line, 3);
    EXPECT_EQ(d.where.column, 20);  // the key's opening quote
    EXPECT_EQ(d.where.pointer, "/Pipelines/0/PSODesc/Nmae");
  }
  EXPECT_TRUE(found) << "no diagnostic for the unknown key";
}

TEST(NotationReader, AMissingImportIsAnErrorNamingIt) {
  Read r(Files{{"/p/main.json", R"({ "Imports": ["nowhere.json"] })"}});
  auto all = r.all();
  ASSERT_FALSE(all.empty());
  EXPECT_NE(all[0].message.find("nowhere.json"), std::string::npos) << all[0].message;
  EXPECT_EQ(all[0].where.pointer, "/Imports/0");
}

TEST(NotationReader, TheSameNameTwiceWithDifferentDefinitionsIsAnError) {
  std::string other = pipeline_json("Twice PSO");
  other.replace(other.find("RGBA8_UNORM"), 11, "RGBA16_FLOAT");
  Read r(Files{{"/p/main.json", R"({ "Pipelines": [)" + pipeline_json("Twice PSO") + "," + other + "] }"},
               {"/p/shaders/screen.hlsl", ""},
               {"/p/shaders/shade.hlsl", ""}});
  bool found = false;
  for (const auto& d : r.all()) found |= d.message.find("Twice PSO") != std::string::npos;
  EXPECT_TRUE(found) << "a redefined pipeline name was not reported";
}

}  // namespace
}  // namespace statepack::packager
