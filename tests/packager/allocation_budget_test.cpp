// The compile-time allocation budget (packager/shaders/allocation_budget.hpp): macros that expand
// exponentially end as an error naming the shader, within seconds, and the process compiles the next
// shader as if nothing had happened.
#include <gtest/gtest.h>
#include <vulkan/vulkan_core.h>

#include <chrono>
#include <new>
#include <sstream>
#include <string>
#include <thread>

#include "shaders/allocation_budget.hpp"
#include "shaders/shader_compiler.hpp"

namespace statepack::packager {
namespace {

std::string chain_of(const std::string& name, int levels, const std::string& base, const std::string& join) {
  std::string text = "#define " + name + "0 " + base + "\n";
  for (int i = 1; i <= levels; ++i) {
    const std::string prev = name + std::to_string(i - 1);
    text += "#define " + name + std::to_string(i) + " (" + prev + join + prev + ")\n";
  }
  return text;
}

const char* kHeader =
    "#version 450\nlayout(local_size_x = 1) in;\n"
    "layout(set = 0, binding = 0) buffer Data { float v; } data;\n";

ShaderDesc compute_shader(const std::string& name, const std::string& body,
                          SourceLanguage language = SourceLanguage::glsl) {
  ShaderDesc desc;
  desc.name = name;
  desc.stage = VK_SHADER_STAGE_COMPUTE_BIT;
  desc.language = language;
  desc.source = body;
  desc.where = {"a.json", 1, 1, "/Shaders/0"};
  return desc;
}

struct Outcome {
  CompiledShader compiled;
  std::string messages;
  double seconds = 0;
};

Outcome compile(const ShaderDesc& desc) {
  Diagnostics diag;
  const auto start = std::chrono::steady_clock::now();
  Outcome out{compile_shader(desc, CompileOptions{}, diag), {}, 0};
  out.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  std::ostringstream text;
  diag.print(text);
  out.messages = text.str();
  return out;
}

TEST(AllocationBudget, RefusesTheAllocationThatPassesItOnceAndCountsOnlyItsThread) {
  if (!allocation_budget_enforced()) GTEST_SKIP() << "sanitizer build: operator new is the sanitizer's";
  AllocationBudget budget(1000);
  void* small = ::operator new(600);
  EXPECT_EQ(budget.used(), 600u);
  // Another thread's allocations are its own (the packer compiles on several).
  std::thread([] { ::operator delete(::operator new(5000)); }).join();
  EXPECT_LE(budget.used(), 1000u);
  EXPECT_FALSE(budget.exhausted());
  EXPECT_THROW(static_cast<void>(::operator new(600)), std::bad_alloc);
  EXPECT_TRUE(budget.exhausted());
  // Off after the refusal: unwinding code may allocate again.
  void* after = ::operator new(600);
  ::operator delete(after);
  ::operator delete(small);
}

TEST(AllocationBudget, RaiseAllowsMore) {
  if (!allocation_budget_enforced()) GTEST_SKIP() << "sanitizer build: operator new is the sanitizer's";
  AllocationBudget budget(1000);
  budget.raise(1000);
  void* p = ::operator new(1500);
  EXPECT_FALSE(budget.exhausted());
  EXPECT_EQ(budget.limit(), 2000u);
  ::operator delete(p);
}

constexpr const char* kBombMessage =
    "a.json:1:1: error: shader 'Bomb': compiling it allocated more than 512 MiB (512 MiB and 512 bytes per "
    "byte of source and includes): does a macro expand exponentially, such as one used twice in the next "
    "one's definition, or F(F(F(...))) with F using its argument twice? [/Shaders/0]\n";

TEST(MacroExpansion, ExponentialMacrosAreStoppedByNameAndTheNextShaderCompilesTheSame) {
  if (!allocation_budget_enforced()) GTEST_SKIP() << "sanitizer build: operator new is the sanitizer's";
  const ShaderDesc good = compute_shader("Good", std::string(kHeader) + "void main() { data.v = 2.0; }\n");
  const Outcome before = compile(good);
  ASSERT_TRUE(before.compiled.ok) << before.messages;

  const std::string nested = "#define F(x) (x + x)\n";
  const ShaderDesc bombs[] = {
      // Object-like macros, each using the last twice, in code: the parse tree grows.
      compute_shader("Bomb", std::string(kHeader) + chain_of("A", 40, "data.v", "+") +
                                 "void main() { data.v = A40; }\n"),
      // A function-like macro nested in its own argument: glslang expands each argument first.
      compute_shader(
          "Bomb", std::string(kHeader) + nested + "void main() { data.v = " +
                      [] {
                        std::string s;
                        for (int i = 0; i < 40; ++i) s += "F(";
                        s += "data.v";
                        for (int i = 0; i < 40; ++i) s += ")";
                        return s;
                      }() +
                      "; }\n"),
      // Inside #if: nothing grows, but every expansion allocates its input stream.
      compute_shader("Bomb", std::string(kHeader) + chain_of("B", 40, "1", "+") +
                                 "#if B40 > 0\n#endif\nvoid main() {}\n"),
      // HLSL goes through the same preprocessor.
      compute_shader(
          "Bomb",
          chain_of("H", 40, "1.0", "+") +
              "RWStructuredBuffer<float> data;\n[numthreads(1, 1, 1)] void main() { data[0] = H40; }\n",
          SourceLanguage::hlsl),
  };
  for (const ShaderDesc& bomb : bombs) {
    const Outcome out = compile(bomb);
    EXPECT_FALSE(out.compiled.ok);
    EXPECT_EQ(out.messages, kBombMessage) << bomb.source.substr(0, 400);
    EXPECT_LT(out.seconds, 30.0);
  }

  const Outcome after = compile(good);
  ASSERT_TRUE(after.compiled.ok) << after.messages;
  EXPECT_EQ(after.compiled.spirv, before.compiled.spirv);
}

TEST(MacroExpansion, BoundedExponentialUnrollingIsNotRefused) {
  // A hand-unrolled loop: 4^6 = 4,096 statements from 6 macro levels, far past the source's size.
  std::string text = std::string(kHeader) + "#define S0 data.v = data.v * 0.5 + 1.0;\n";
  for (int i = 1; i <= 6; ++i) {
    const std::string prev = "S" + std::to_string(i - 1);
    text += "#define S" + std::to_string(i) + " " + prev + " " + prev + " " + prev + " " + prev + "\n";
  }
  text += "void main() { S6 }\n";
  const Outcome out = compile(compute_shader("Unrolled", text));
  EXPECT_TRUE(out.compiled.ok) << out.messages;
  EXPECT_EQ(out.messages, "");
}

}  // namespace
}  // namespace statepack::packager
