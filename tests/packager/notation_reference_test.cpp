// The enum reference that docs/notation.md is generated from: it must cover every table the reader has,
// and the generated section must be spliced between its markers and nowhere else.
#include <gtest/gtest.h>

#include <algorithm>
#include <fstream>
#include <regex>
#include <set>
#include <sstream>

#include "notation/enum_tables.hpp"
#include "notation/notation_reference.hpp"

namespace {

using namespace statepack::packager;

// A table added to enum_tables.hpp without a registry entry would be missing from the docs.
TEST(NotationReference, EveryTableOfTheReaderIsRegistered) {
  std::ifstream file(STATEPACK_ENUM_TABLES_HEADER);
  ASSERT_TRUE(file) << STATEPACK_ENUM_TABLES_HEADER;
  std::stringstream text;
  text << file.rdbuf();
  const std::string header = text.str();
  const std::regex table(R"(inline constexpr EnumEntry (k\w+)\[\])");
  size_t tables =
      std::distance(std::sregex_iterator(header.begin(), header.end(), table), std::sregex_iterator());
  EXPECT_GE(tables, 25u);
  EXPECT_EQ(std::size(kEnumTableInfo), tables);
  std::set<const EnumEntry*> distinct;
  for (const auto& info : kEnumTableInfo) distinct.insert(info.values.data());
  EXPECT_EQ(distinct.size(), std::size(kEnumTableInfo)) << "a table is registered twice";
}

TEST(NotationReference, ValuesAreSplitIntoAcceptedAndRefused) {
  auto enums = enum_reference();
  auto find = [&](std::string_view name) {
    return *std::find_if(enums.begin(), enums.end(), [&](const EnumReference& e) { return e.name == name; });
  };
  const EnumReference types = find("SHADER_TYPE");
  EXPECT_FALSE(types.bit_flags);
  EXPECT_EQ(types.accepted.front(), "VERTEX");
  EXPECT_NE(std::find(types.refused.begin(), types.refused.end(), "MESH"), types.refused.end());
  EXPECT_EQ(std::find(types.accepted.begin(), types.accepted.end(), "MESH"), types.accepted.end());
  const EnumReference stages = find("SHADER_TYPE (stage flags)");
  EXPECT_TRUE(stages.bit_flags);
  EXPECT_NE(std::find(stages.accepted.begin(), stages.accepted.end(), "VS_PS"), stages.accepted.end());
  EXPECT_EQ(find("BLEND_OPERATION").keys,
            (std::vector<std::string_view>{"RenderTargets[].BlendOp", "RenderTargets[].BlendOpAlpha"}));
  const std::string md = enum_reference_markdown(enums);
  EXPECT_NE(md.find("### PRIMITIVE_TOPOLOGY\n\nKeys: `GraphicsPipeline.PrimitiveTopology`. One name.\n\n"
                    "Values: `TRIANGLE_LIST`, `TRIANGLE_STRIP`, `POINT_LIST`"),
            std::string::npos)
      << md;
}

TEST(NotationReference, GeneratedSectionIsReplacedBetweenItsMarkers) {
  const std::string doc = "# Title\n\n" + std::string(kGeneratedBegin) + "\nold text\n" +
                          std::string(kGeneratedEnd) + "\n\nafter\n";
  EXPECT_EQ(with_generated_section(doc, "new\n"), "# Title\n\n" + std::string(kGeneratedBegin) + "\nnew\n" +
                                                      std::string(kGeneratedEnd) + "\n\nafter\n");
  EXPECT_EQ(with_generated_section("no markers\n", "new\n"), std::nullopt);
  EXPECT_EQ(
      with_generated_section(std::string(kGeneratedEnd) + "\n" + std::string(kGeneratedBegin) + "\n", "x"),
      std::nullopt);
}

}  // namespace
