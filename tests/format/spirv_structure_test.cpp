// The SPIR-V structure check (format/spirv_structure.cpp): every module of every test archive passes it
// (glslang's and spirv-opt's output, HLSL and GLSL, both backends), and small hand-assembled modules
// broken in one way each are refused with a message naming the instruction, the word and the id.
#include <gtest/gtest.h>

#include <initializer_list>
#include <string>
#include <vector>

#include "common/vulkan_test_fixture.hpp"
#include "format/spirv_structure.hpp"
#include "format/spirv_walk.hpp"
#include "runtime/archive_access.hpp"

namespace statepack::testing {
namespace {

// A module assembled instruction by instruction: op(opcode, operands) appends one, the word count is
// computed; text() packs a nul-terminated literal string.
struct Assembler {
  std::vector<uint32_t> words{0x07230203u, 0x00010000u, 0, 0, 0};
  void op(uint32_t opcode, std::initializer_list<uint32_t> operands) {
    words.push_back(uint32_t(operands.size() + 1) << 16 | opcode);
    words.insert(words.end(), operands);
  }
  static std::vector<uint32_t> text(const std::string& s) {
    std::vector<uint32_t> out(s.size() / 4 + 1, 0);
    for (size_t i = 0; i < s.size(); ++i) out[i / 4] |= uint32_t(uint8_t(s[i])) << (8 * (i % 4));
    return out;
  }
  void op(uint32_t opcode, std::vector<uint32_t> operands) {
    words.push_back(uint32_t(operands.size() + 1) << 16 | opcode);
    words.insert(words.end(), operands.begin(), operands.end());
  }
  std::vector<uint32_t> finish(uint32_t bound) {
    words[3] = bound;
    return words;
  }
};

// Ids of the minimal compute module below; types and constants between `declare` and the function.
enum : uint32_t { kVoid = 1, kFunctionType = 2, kMain = 3, kLabel = 4, kUint = 5, kFirstFree = 6 };

// OpCapability Shader, OpMemoryModel Logical GLSL450, OpEntryPoint GLCompute %main "main",
// OpExecutionMode LocalSize 1 1 1, %void, %fn = OpTypeFunction %void, %uint = OpTypeInt 32 0,
// then `declare`'s instructions, then %main with one block that returns.
// OpCapability Shader, OpMemoryModel Logical GLSL450, OpEntryPoint GLCompute %main "main": how every
// module of these tests begins.
void begin_module(Assembler& a) {
  a.op(17, {1});
  a.op(14, {0, 1});
  std::vector<uint32_t> entry{5, kMain};
  for (uint32_t w : Assembler::text("main")) entry.push_back(w);
  a.op(15, entry);
}

template <typename Declare>
std::vector<uint32_t> compute_module(Declare declare, uint32_t bound = 64) {
  Assembler a;
  begin_module(a);
  a.op(16, {kMain, 17, 1, 1, 1});
  a.op(19, {kVoid});
  a.op(33, {kFunctionType, kVoid});
  a.op(21, {kUint, 32, 0});
  declare(a);
  a.op(54, {kVoid, kMain, 0, kFunctionType});
  a.op(248, {kLabel});
  a.op(253, {});
  a.op(56, {});
  return a.finish(bound);
}
std::vector<uint32_t> compute_module() {
  return compute_module([](Assembler&) {});
}

std::string error_of(const std::vector<uint32_t>& words) {
  auto ok = spirv::check_structure(words);
  return ok ? "" : ok.error().message;
}

// The error for the minimal module with `declarations` (opcode, operands) among its types.
std::string error_declaring(std::initializer_list<std::pair<uint32_t, std::vector<uint32_t>>> declarations) {
  return error_of(compute_module([&](Assembler& a) {
    for (const auto& [opcode, operands] : declarations) a.op(opcode, operands);
  }));
}

TEST(SpirvStructure, EveryModuleOfTheTestArchivesPasses) {
  std::vector<std::string> paths = corpus_archives();
  paths.push_back(STATEPACK_TEST_ARCHIVE);
  paths.push_back(STATEPACK_GL_SLICE_ARCHIVE);
  size_t modules = 0;
  for (const auto& path : paths) {
    auto archive = Archive::from_file(path);
    ASSERT_TRUE(archive) << path << ": " << archive.error().message;
    const auto& c = detail::ArchiveAccess::contents(*archive);
    for (size_t i = 0; i < c.spirv.size(); ++i, ++modules) {
      auto ok = spirv::check_structure(c.spirv[i]);
      EXPECT_TRUE(ok) << path << " blob " << i << ": " << ok.error().message;
    }
  }
  EXPECT_GT(modules, 20u);
}

TEST(SpirvStructure, TheMinimalModulePasses) {
  EXPECT_EQ(error_of(compute_module()), "");
  EXPECT_TRUE(spirv::walk(compute_module()));
}

TEST(SpirvStructure, AnUndefinedElementTypeIsRefused) {
  // The case that crashed the validation layer: a runtime array of an id nothing defines.
  const auto words = compute_module([](Assembler& a) { a.op(29, {kFirstFree, 40}); });
  EXPECT_EQ(error_of(words),
            "SPIR-V OpTypeRuntimeArray at word 30: type operand %40 is not defined before its use "
            "(outside functions, SPIR-V defines before it uses)");
  EXPECT_FALSE(spirv::walk(words));
}

TEST(SpirvStructure, AnElementTypeThatIsNotATypeIsRefused) {
  const auto words = compute_module([](Assembler& a) {
    a.op(43, {kUint, kFirstFree, 7});        // %6 = OpConstant %uint 7
    a.op(29, {kFirstFree + 1, kFirstFree});  // OpTypeRuntimeArray %6
  });
  EXPECT_EQ(error_of(words),
            "SPIR-V OpTypeRuntimeArray at word 34: type operand %6 is defined by OpConstant, not a type");
}

TEST(SpirvStructure, ResultTypesMustBeTypesDefinedBefore) {
  EXPECT_EQ(error_declaring({{43, {30, kFirstFree, 7}}}),
            "SPIR-V OpConstant at word 30: result type %30 is not defined before its use");
  EXPECT_EQ(error_declaring({{43, {kUint, kFirstFree, 7}}, {43, {kFirstFree, kFirstFree + 1, 7}}}),
            "SPIR-V OpConstant at word 34: result type %6 is not a type");
}

TEST(SpirvStructure, IdsOutsideTheBoundAndTwiceDefinedResultsAreRefused) {
  EXPECT_EQ(error_declaring({{29, {kFirstFree, 64}}}),
            "SPIR-V OpTypeRuntimeArray at word 30: operand %64 is outside the module's id bound 64");
  EXPECT_EQ(error_declaring({{29, {kFirstFree, 0}}}),
            "SPIR-V OpTypeRuntimeArray at word 30: operand %0 is outside the module's id bound 64");
  EXPECT_EQ(error_declaring({{29, {kUint, kUint}}}),
            "SPIR-V OpTypeRuntimeArray at word 30: result %5 is defined twice");
}

TEST(SpirvStructure, OperandCountsFollowTheGrammar) {
  EXPECT_EQ(error_declaring({{21, {kFirstFree, 32}}}),
            "SPIR-V OpTypeInt at word 30: has fewer operands than its grammar requires");
  EXPECT_EQ(error_declaring({{29, {kFirstFree, kUint, 9}}}),
            "SPIR-V OpTypeRuntimeArray at word 30: has 1 words more than its operands");
  // A 64-bit constant takes two words; one is too few.
  EXPECT_EQ(error_declaring({{21, {kFirstFree, 64, 0}}, {43, {kFirstFree, kFirstFree + 1, 7}}}),
            "SPIR-V OpConstant at word 34: has a constant narrower than its type");
  EXPECT_EQ(error_declaring({{21, {kFirstFree, 64, 0}}, {43, {kFirstFree, kFirstFree + 1, 7, 0}}}), "");
}

TEST(SpirvStructure, StringsMustEndAndOpcodesMustExist) {
  EXPECT_EQ(error_declaring({{5, {kMain, 0x6e69616d}}}),  // "main", no nul
            "SPIR-V OpName at word 30: has a literal string without its terminating nul");
  EXPECT_EQ(error_declaring({{5, {kMain, 0x6e69616d, 0}}}), "");
  EXPECT_EQ(error_declaring({{9999, {1}}}),
            std::string("SPIR-V instruction at word 30: opcode 9999 is not one of SPIR-V ") +
                spirv::grammar_version() + "'s");
}

TEST(SpirvStructure, KindsSpirvRequiresOfParticularOperands) {
  EXPECT_EQ(error_declaring({{59, {kUint, kFirstFree, 6}}}),
            "SPIR-V OpVariable at word 30: variable %6 has type %5, not a pointer");
  EXPECT_EQ(error_declaring({{43, {kVoid, kFirstFree, 1}}}),
            "SPIR-V OpConstant at word 30: constant %6 has type %1, not an integer or float type");
  // An array's length is an integer constant, not a type.
  EXPECT_EQ(error_declaring({{28, {kFirstFree, kUint, kUint}}}),
            "SPIR-V OpTypeArray at word 30: array length %5 is not an integer constant");
}

TEST(SpirvStructure, ForwardReferencesOnlyWhereSpirvAllowsThem) {
  // A decoration names what comes after it (OpDecorate %6 ArrayStride 16, then %6 = an array); a
  // constant composite may not (a uvec2 of %20, defined after it).
  EXPECT_EQ(error_declaring({{71, {kFirstFree, 6, 16}},
                             {43, {kUint, kFirstFree + 1, 4}},
                             {28, {kFirstFree, kUint, kFirstFree + 1}}}),
            "");
  EXPECT_EQ(
      error_declaring(
          {{23, {kFirstFree, kUint, 2}}, {44, {kFirstFree, kFirstFree + 1, 20, 20}}, {43, {kUint, 20, 4}}}),
      "SPIR-V OpConstantComposite at word 34: operand %20 is not defined before its use "
      "(outside functions, SPIR-V defines before it uses)");
  // A name for nothing the module ever defines.
  EXPECT_EQ(error_declaring({{5, {40, 0}}}), "SPIR-V OpName at word 30: operand %40 is never defined");
}

TEST(SpirvStructure, ADecorationsOperandsAreReadByItsKind) {
  // OpDecorate %uint SpecId: one literal more; BuiltIn: its value; without: none.
  EXPECT_EQ(error_declaring({{71, {kUint, 1, 3}}}), "");
  EXPECT_EQ(error_declaring({{71, {kUint, 1}}}),
            "SPIR-V OpDecorate at word 30: has fewer operands than its grammar requires");
  EXPECT_EQ(error_declaring({{71, {kUint, 2, 3}}}),
            "SPIR-V OpDecorate at word 30: has 1 words more than its operands");
}

TEST(SpirvStructure, AHugeBoundCostsNoHugeTable) {
  // The largest bound SPIR-V allows, on a module of a few dozen words: checked like any other.
  EXPECT_EQ(error_of(compute_module([](Assembler&) {}, 4194303)), "");
  EXPECT_EQ(error_of(compute_module(
                [](Assembler& a) {
                  a.op(29, {4000000, 4100000});
                },
                4194303)),
            "SPIR-V OpTypeRuntimeArray at word 30: type operand %4100000 is not defined before its use "
            "(outside functions, SPIR-V defines before it uses)");
}

}  // namespace
}  // namespace statepack::testing

namespace statepack::testing {
namespace {

// A block's terminators, as the walker closes blocks: OpDemoteToHelperInvocation (5380) continues the
// block, OpEmitMeshTasksEXT (5294) ends it. (The walker once had the two numbers swapped, refusing every
// module that demotes and every task shader.)
std::vector<uint32_t> module_with_body(
    std::initializer_list<std::pair<uint32_t, std::vector<uint32_t>>> body) {
  Assembler a;
  begin_module(a);
  a.op(19, {kVoid});
  a.op(33, {kFunctionType, kVoid});
  a.op(54, {kVoid, kMain, 0, kFunctionType});
  a.op(248, {kLabel});
  for (const auto& [opcode, operands] : body) a.op(opcode, operands);
  a.op(56, {});
  return a.finish(64);
}

// The walk keeps what it reads by id in a table indexed by id when the bound is near the module's size,
// and in a hash map when a header claims a bound far beyond it: both must read the same facts.
TEST(SpirvWalk, ASmallAndAHugeBoundReadTheSameDeclarations) {
  auto module = [](uint32_t bound) {
    return compute_module(
        [](Assembler& a) {
          a.op(71, {10, 34, 0});  // %10: DescriptorSet 0, Binding 3
          a.op(71, {10, 33, 3});
          a.op(71, {13, 34, 0});  // %13: DescriptorSet 0, Binding 4
          a.op(71, {13, 33, 4});
          a.op(71, {8, 2});         // %8: Block
          a.op(72, {8, 0, 35, 0});  // member 0 at offset 0
          a.op(71, {7, 6, 4});      // %7: ArrayStride 4
          a.op(71, {14, 1, 7});     // %14: SpecId 7
          a.op(71, {15, 2});
          a.op(72, {15, 0, 35, 0});
          a.op(43, {kUint, 6, 4});  // %6 = 4
          a.op(28, {7, kUint, 6});  // %7 = uint[4]
          a.op(30, {8, 7});         // %8 = struct { uint[4] }
          a.op(32, {9, 2, 8});      // Uniform pointer to %8
          a.op(59, {9, 10, 2});     // %10: a uniform buffer
          a.op(28, {11, 8, 6});     // %11 = %8[4]
          a.op(32, {12, 2, 11});
          a.op(59, {12, 13, 2});     // %13: four uniform buffers
          a.op(50, {kUint, 14, 1});  // %14: a specialization constant
          a.op(30, {15, kUint});     // %15 = struct { uint }
          a.op(32, {16, 9, 15});     // PushConstant pointer to %15
          a.op(59, {16, 17, 9});     // %17: push constants
        },
        bound);
  };
  auto small = spirv::walk(module(64));
  auto huge = spirv::walk(module(4194303));
  ASSERT_TRUE(small) << small.error().message;
  ASSERT_TRUE(huge) << huge.error().message;
  for (const spirv::Module* m : {&*small, &*huge}) {
    ASSERT_EQ(m->resources.size(), 2u);
    const uint32_t uniform_buffer = 1u << 6 | 1u << 8;  // UNIFORM_BUFFER or its dynamic form
    EXPECT_EQ(m->resources[0].binding, 3u);
    EXPECT_EQ(m->resources[0].array_size, 1u);
    EXPECT_EQ(m->resources[0].compatible, uniform_buffer);
    EXPECT_EQ(m->resources[1].binding, 4u);
    EXPECT_EQ(m->resources[1].array_size, 4u);
    EXPECT_EQ(m->resources[1].compatible, uniform_buffer);
    ASSERT_TRUE(m->push_constants);
    EXPECT_EQ(m->push_constants->size, 4u);
    ASSERT_EQ(m->spec_constants.size(), 1u);
    EXPECT_EQ(m->spec_constants[0].constant_id, 7u);
    EXPECT_EQ(m->spec_constants[0].size, 4u);
    ASSERT_EQ(m->entry_points.size(), 1u);
    ASSERT_TRUE(m->entry_points[0].workgroup_size);
    EXPECT_EQ((*m->entry_points[0].workgroup_size)[0].value, 1u);
  }
}

TEST(SpirvWalk, DemoteContinuesItsBlockAndEmitMeshTasksEndsIt) {
  auto demote = spirv::walk(module_with_body({{5380, {}}, {253, {}}}));  // demote, then OpReturn
  EXPECT_TRUE(demote) << demote.error().message;
  auto tasks = spirv::walk(module_with_body({{5294, {kLabel, kLabel, kLabel}}}));  // the block's last
  EXPECT_TRUE(tasks) << tasks.error().message;
  auto unterminated = spirv::walk(module_with_body({{5380, {}}}));
  ASSERT_FALSE(unterminated);
  EXPECT_EQ(unterminated.error().message,
            "SPIR-V word 28: OpFunctionEnd outside a function or inside a block");
}

}  // namespace
}  // namespace statepack::testing
