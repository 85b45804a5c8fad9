// The packager's own SPIR-V rewrites, each on modules glslang compiles here and each result validated by
// SPIRV-Tools: HLSL vertex inputs placed by semantic, a uniform block made push constants (inline
// constants), per-stage views of a block merged for OpenGL; and the shader environment they compile in.
#include <gtest/gtest.h>
#include <vulkan/vulkan_core.h>
#include <spirv-tools/libspirv.hpp>

#include <algorithm>

#include "layout/block_views.hpp"
#include "shaders/hlsl_vertex_inputs.hpp"
#include "shaders/push_constant_conversion.hpp"
#include "shaders/shader_compiler.hpp"
#include "shaders/shader_environment.hpp"
#include "shaders/spirv_reflect.hpp"

namespace statepack::packager {
namespace {

ShaderDesc inline_shader(std::string source, uint32_t stage, SourceLanguage language,
                         std::string entry = "main") {
  ShaderDesc s;
  s.name = "test";
  s.stage = stage;
  s.language = language;
  s.source = std::move(source);
  s.entry_point = std::move(entry);
  return s;
}

CompiledShader compile(const ShaderDesc& shader, const CompileOptions& options = {}) {
  Diagnostics diag;
  CompiledShader out = compile_shader(shader, options, diag);
  EXPECT_TRUE(out.ok) << (diag.all().empty() ? std::string() : diag.all().front().message);
  return out;
}

std::string validate(const std::vector<uint32_t>& spirv, spv_target_env env = SPV_ENV_VULKAN_1_0) {
  std::string messages;
  spvtools::SpirvTools tools(env);
  tools.SetMessageConsumer([&](spv_message_level_t, const char*, const spv_position_t&, const char* m) {
    messages += m;
    messages += '\n';
  });
  return tools.Validate(spirv) ? "" : messages;
}

std::string disassemble(const std::vector<uint32_t>& spirv) {
  std::string text;
  spvtools::SpirvTools(SPV_ENV_VULKAN_1_0)
      .Disassemble(spirv, &text, SPV_BINARY_TO_TEXT_OPTION_FRIENDLY_NAMES);
  return text;
}

TEST(VertexSemantics, AttribIndexAndDirect3DMatching) {
  EXPECT_EQ(attrib_index("ATTRIB0"), 0u);
  EXPECT_EQ(attrib_index("attrib12"), 12u);  // any case, as Diligent
  EXPECT_EQ(attrib_index("ATTRIB"), 0u);
  EXPECT_FALSE(attrib_index("ATTRIBX"));
  EXPECT_FALSE(attrib_index("TEXCOORD0"));
  EXPECT_FALSE(attrib_index("ATTRIB99999999999"));  // no overflow into a small location
  EXPECT_TRUE(semantic_matches("TEXCOORD2", "TEXCOORD", 2));
  EXPECT_TRUE(semantic_matches("texcoord", "TEXCOORD", 0));
  EXPECT_FALSE(semantic_matches("TEXCOORD", "TEXCOORD", 1));
  EXPECT_FALSE(semantic_matches("TEXCOORD02", "TEXCOORD", 2));
  EXPECT_FALSE(semantic_matches("TEXCOORDS", "TEXCOORD", 0));
}

// ATTRIBn inputs read location n whatever their order; glslang's semantic decorations are stripped (no
// driver needs SPV_GOOGLE_hlsl_functionality1) but the semantics are kept.
TEST(VertexSemantics, HlslInputsArePlacedAndTheDecorationsStripped) {
  const CompiledShader vs = compile(inline_shader(
      "float4 main(float2 UV : ATTRIB3, float3 Pos : ATTRIB0, float4 Color : COLOR) : SV_POSITION {"
      " return float4(Pos + Color.xyz, UV.x); }",
      VK_SHADER_STAGE_VERTEX_BIT, SourceLanguage::hlsl));
  EXPECT_EQ(validate(vs.spirv), "");
  const std::string text = disassemble(vs.spirv);
  EXPECT_EQ(text.find("hlsl_functionality1"), std::string::npos) << text;
  EXPECT_EQ(text.find("UserSemantic"), std::string::npos) << text;
  const Reflection r = reflect_spirv(vs.spirv, VK_SHADER_STAGE_VERTEX_BIT);
  auto location_of = [&](const std::string& name) {
    for (const InterfaceVariable& v : r.inputs)
      if (v.name == name) return int(v.location);
    return -1;
  };
  EXPECT_EQ(location_of("UV"), 3);
  EXPECT_EQ(location_of("Pos"), 0);
  EXPECT_EQ(location_of("Color"), 2);  // not ATTRIBn: glslang's place, its third declared input
  ASSERT_EQ(vs.vertex_semantics.size(), 3u);
  EXPECT_TRUE(std::any_of(vs.vertex_semantics.begin(), vs.vertex_semantics.end(),
                          [](const VertexInputSemantic& s) { return s.semantic == "COLOR"; }));
}

// A uniform block becomes the module's push constants: every pointer into it follows, its descriptor
// decorations go, its offsets stay; the result is valid and reflects as push constants of that size.
TEST(InlineConstants, AUniformBlockBecomesThePushConstants) {
  const CompiledShader fs = compile(inline_shader(R"(#version 450
struct Light { vec4 color; float power; };
layout(set = 0, binding = 3) uniform Draw { vec4 tint; Light lights[2]; int which; } draw;
layout(set = 0, binding = 4) uniform Other { vec4 other; } other;
layout(location = 0) out vec4 o;
void main() { o = draw.tint * draw.lights[draw.which].color * draw.lights[1].power + other.other; }
)",
                                                  VK_SHADER_STAGE_FRAGMENT_BIT, SourceLanguage::glsl));
  Reflection before = reflect_spirv(fs.spirv, VK_SHADER_STAGE_FRAGMENT_BIT);
  auto draw = std::find_if(before.bindings.begin(), before.bindings.end(),
                           [](const ReflectedBinding& b) { return b.binding == 3; });
  ASSERT_NE(draw, before.bindings.end());
  std::vector<uint32_t> spirv = fs.spirv;
  ASSERT_EQ(uniform_block_to_push_constants(spirv, draw->variable), "");
  EXPECT_EQ(validate(spirv), "");
  const Reflection after = reflect_spirv(spirv, VK_SHADER_STAGE_FRAGMENT_BIT);
  EXPECT_EQ(after.push_constant_size, draw->block_size);
  ASSERT_EQ(after.bindings.size(), 1u);
  EXPECT_EQ(after.bindings[0].binding, 4u);
  // Once it has push constants, another block cannot become them too; a storage buffer never can.
  EXPECT_NE(
      uniform_block_to_push_constants(spirv, after.bindings[0].variable).find("push constants of its own"),
      std::string::npos);
  const CompiledShader cs = compile(inline_shader(
      "#version 450\nlayout(local_size_x = 1) in;\nlayout(binding = 0) buffer B { uint v; } b;\n"
      "void main() { b.v = 1u; }\n",
      VK_SHADER_STAGE_COMPUTE_BIT, SourceLanguage::glsl));
  std::vector<uint32_t> storage = cs.spirv;
  const Reflection r = reflect_spirv(storage, VK_SHADER_STAGE_COMPUTE_BIT);
  ASSERT_EQ(r.bindings.size(), 1u);
  EXPECT_NE(uniform_block_to_push_constants(storage, r.bindings[0].variable), "");
}

// Per-stage views of one block: merged into one definition in every module when they agree where they
// overlap (members the other stage lacks are declared in it, nested structs and arrays included); a
// conflict is named.
TEST(BlockViews, ViewsThatAgreeAreMergedAndConflictsNamed) {
  CompileOptions gl;
  gl.opengl = true;  // the views are merged in the OpenGL modules
  const CompiledShader vs = compile(inline_shader(R"(#version 450
struct Light { vec4 color; float power[2]; };
layout(binding = 0, std140) uniform Params { mat4 transform; Light light; } params;
void main() { gl_Position = params.transform * params.light.color * params.light.power[1]; }
)",
                                                  VK_SHADER_STAGE_VERTEX_BIT, SourceLanguage::glsl),
                                    gl);
  const CompiledShader fs = compile(inline_shader(R"(#version 450
layout(binding = 0, std140) uniform Params { layout(offset = 112) vec4 tint; float gain; } params;
layout(location = 0) out vec4 o;
void main() { o = params.tint * params.gain; }
)",
                                                  VK_SHADER_STAGE_FRAGMENT_BIT, SourceLanguage::glsl),
                                    gl);
  auto variable_of = [](const std::vector<uint32_t>& spirv, uint32_t stage) {
    const Reflection r = reflect_spirv(spirv, stage);
    return r.bindings.empty() ? 0u : r.bindings[0].variable;
  };
  std::vector<uint32_t> a = vs.spirv, b = fs.spirv;
  std::vector<BlockView> views{{&a, variable_of(a, VK_SHADER_STAGE_VERTEX_BIT), "vertex shader 'A'"},
                               {&b, variable_of(b, VK_SHADER_STAGE_FRAGMENT_BIT), "pixel shader 'B'"}};
  EXPECT_EQ(block_views_conflict(views), "");
  ASSERT_EQ(merge_block_views(views), "");
  EXPECT_EQ(validate(a, SPV_ENV_OPENGL_4_5), "");
  EXPECT_EQ(validate(b, SPV_ENV_OPENGL_4_5), "");
  const Reflection ra = reflect_spirv(a, VK_SHADER_STAGE_VERTEX_BIT);
  const Reflection rb = reflect_spirv(b, VK_SHADER_STAGE_FRAGMENT_BIT);
  ASSERT_EQ(ra.bindings.size(), 1u);
  ASSERT_EQ(rb.bindings.size(), 1u);
  EXPECT_EQ(ra.bindings[0].block_layout, rb.bindings[0].block_layout) << "one definition in both";
  EXPECT_EQ(ra.bindings[0].block_size, 132u);  // mat4, Light (vec4 + float[2] of stride 16), vec4, float

  // A float over the matrix's bytes conflicts: named, and the modules are left as they were.
  const CompiledShader clash = compile(inline_shader(R"(#version 450
layout(binding = 0, std140) uniform Params { layout(offset = 4) float gain; } params;
layout(location = 0) out vec4 o;
void main() { o = vec4(params.gain); }
)",
                                                     VK_SHADER_STAGE_FRAGMENT_BIT, SourceLanguage::glsl),
                                       gl);
  std::vector<uint32_t> c = vs.spirv, d = clash.spirv;
  const std::vector<uint32_t> c_before = c, d_before = d;
  std::vector<BlockView> conflicting{{&c, variable_of(c, VK_SHADER_STAGE_VERTEX_BIT), "vertex shader 'A'"},
                                     {&d, variable_of(d, VK_SHADER_STAGE_FRAGMENT_BIT), "pixel shader 'C'"}};
  const std::string conflict = merge_block_views(conflicting);
  EXPECT_NE(conflict.find("'transform' (64 bytes at offset 0) in vertex shader 'A' and 'gain' (4 bytes at "
                          "offset 4) in pixel shader 'C' overlap"),
            std::string::npos)
      << conflict;
  EXPECT_EQ(c, c_before);
  EXPECT_EQ(d, d_before);
}

// HLSL's `cbuffer ubo { UBO ubo; }` with a struct one stage declares in part (its first members): the
// larger struct is the view, declared in both modules, and the shorter stage's accesses keep working.
// (Merged here in the Vulkan modules: the OpenGL ones are translated from them, with the same blocks.)
TEST(BlockViews, AStructDeclaredInPartIsMerged) {
  const CompileOptions vulkan;
  const CompiledShader vs = compile(
      inline_shader(
          "struct UBO { float4x4 projection; float4 tint; };\ncbuffer ubo : register(b0) { UBO ubo; }\n"
          "float4 main(float4 p : ATTRIB0) : SV_POSITION { return mul(ubo.projection, p) * ubo.tint; }",
          VK_SHADER_STAGE_VERTEX_BIT, SourceLanguage::hlsl),
      vulkan);
  const CompiledShader fs =
      compile(inline_shader("struct UBO { float4x4 projection; float4 tint; float exposure; };\n"
                            "cbuffer ubo : register(b0) { UBO ubo; }\n"
                            "float4 main() : SV_TARGET { return ubo.tint * ubo.exposure; }",
                            VK_SHADER_STAGE_FRAGMENT_BIT, SourceLanguage::hlsl),
              vulkan);
  std::vector<uint32_t> a = vs.spirv, b = fs.spirv;
  const Reflection before_a = reflect_spirv(a, VK_SHADER_STAGE_VERTEX_BIT);
  const Reflection before_b = reflect_spirv(b, VK_SHADER_STAGE_FRAGMENT_BIT);
  ASSERT_EQ(before_a.bindings.size(), 1u);
  ASSERT_EQ(before_b.bindings.size(), 1u);
  EXPECT_NE(before_a.bindings[0].block_layout, before_b.bindings[0].block_layout);
  std::vector<BlockView> views{{&a, before_a.bindings[0].variable, "vertex shader 'A'"},
                               {&b, before_b.bindings[0].variable, "pixel shader 'B'"}};
  ASSERT_EQ(merge_block_views(views), "");
  EXPECT_EQ(validate(a), "");
  EXPECT_EQ(validate(b), "");
  EXPECT_EQ(reflect_spirv(a, VK_SHADER_STAGE_VERTEX_BIT).bindings[0].block_layout,
            reflect_spirv(b, VK_SHADER_STAGE_FRAGMENT_BIT).bindings[0].block_layout);
}

// Diligent's environment: its definitions for HLSL, its macros for every language, and nothing of it
// with --shader-environment none (the compile flags still take effect).
TEST(ShaderEnvironment, DiligentsNamesAreDefinedAndCanBeLeftOut) {
  ShaderDesc hlsl = inline_shader(
      "float4 main() : SV_TARGET { float4x4 m = MatrixFromRows(float4(1,0,0,0), float4(0,1,0,0),"
      " float4(0,0,1,0), float4(0,0,0,1)); return m[0] * NDC_MIN_Z; }",
      VK_SHADER_STAGE_FRAGMENT_BIT, SourceLanguage::hlsl);
  const CompileOptions options;
  const std::string preamble = shader_environment(hlsl, options).preamble;
  for (const char* name : {"#define GLSLANG", "#define HLSL", "#define PIXEL_SHADER 1",
                           "#define FRAGMENT_SHADER 1", "MatrixFromRows", "NormalizedDeviceXYToTexUV"})
    EXPECT_NE(preamble.find(name), std::string::npos) << name;
  EXPECT_TRUE(environment_defines(hlsl, options, "PIXEL_SHADER"));
  EXPECT_FALSE(environment_defines(hlsl, options, "VERTEX_SHADER"));
  EXPECT_TRUE(compile(hlsl).ok);

  CompileOptions none;
  none.shader_environment = false;
  Diagnostics diag;
  EXPECT_FALSE(compile_shader(hlsl, none, diag).ok);
  ASSERT_FALSE(diag.all().empty());
  EXPECT_NE(diag.all().front().message.find("MatrixFromRows"), std::string::npos)
      << diag.all().front().message;

  ShaderDesc glsl = inline_shader("void main() {}", VK_SHADER_STAGE_COMPUTE_BIT, SourceLanguage::glsl);
  glsl.compile_flags = 8;  // PACK_MATRIX_ROW_MAJOR
  const std::string glsl_preamble = shader_environment(glsl, options).preamble;
  EXPECT_NE(glsl_preamble.find("layout(row_major) uniform;"), std::string::npos);
  EXPECT_NE(glsl_preamble.find("#define COMPUTE_SHADER 1"), std::string::npos);
  EXPECT_NE(glsl_preamble.find("#define _NDC_ZERO_TO_ONE 1"), std::string::npos);
  EXPECT_EQ(shader_environment(glsl, none).preamble, "layout(row_major) uniform;\n");
  glsl.verbatim = true;  // GLSL_VERBATIM: GLSLANG and the flags' effects only, as in Diligent
  EXPECT_EQ(shader_environment(glsl, options).preamble, "layout(row_major) uniform;\n#define GLSLANG\n");
  EXPECT_EQ(shader_environment(glsl, options).default_glsl_version, 460);
}

// glslang reports an error in the text statepack puts before a shader at "-1:N", a place nobody can find:
// each is placed where the notation writes what made that line (a Macros entry, GLSLExtensions), or at
// the shader for -D and the environment, and names it; every language, and with a line put first.
TEST(ShaderEnvironment, AnErrorInTheTextBeforeTheShaderIsPlacedWhereThatTextIsWritten) {
  const Location shader_at{"a.json", 2, 39, "/Pipelines/0/pCS"};
  const Location macro_at{"a.json", 3, 15, "/Pipelines/0/pCS/Macros/1"};
  const Location extensions_at{"a.json", 4, 7, "/Pipelines/0/pCS/GLSLExtensions"};
  auto first_error = [](const ShaderDesc& shader, const CompileOptions& options) {
    Diagnostics diag;
    EXPECT_FALSE(compile_shader(shader, options, diag).ok);
    return diag.all().empty() ? Diagnostic{} : diag.all().front();
  };
  auto with_macros = [&](ShaderDesc s, std::string bad_name, std::string bad_value) {
    s.where = shader_at;
    s.macros = {{"GOOD", "1"}, {std::move(bad_name), std::move(bad_value)}, {"LATER", "2"}};
    s.macro_where = {Location{"a.json", 3, 5, "/Pipelines/0/pCS/Macros/0"}, macro_at,
                     Location{"a.json", 3, 40, "/Pipelines/0/pCS/Macros/2"}};
    return s;
  };
  const ShaderDesc glsl = inline_shader("#version 450\nlayout(local_size_x = 1) in;\nvoid main() {}\n",
                                        VK_SHADER_STAGE_COMPUTE_BIT, SourceLanguage::glsl);
  const ShaderDesc hlsl = inline_shader("[numthreads(1, 1, 1)] void main() {}", VK_SHADER_STAGE_COMPUTE_BIT,
                                        SourceLanguage::hlsl);
  ShaderDesc arb = glsl;  // (gets a line put before the preamble: the include extension's other name)
  arb.source.insert(arb.source.find('\n') + 1, "#extension GL_ARB_shading_language_include : enable\n");
  const CompileOptions options;
  for (const ShaderDesc* base : std::initializer_list<const ShaderDesc*>{&glsl, &hlsl, &arb}) {
    for (auto [name, value, said] : std::initializer_list<std::tuple<const char*, const char*, const char*>>{
             {"X(", "2", "bad argument"}, {"GOOD", "1\n#define GOOD 3", "Macro redefined"}}) {
      const Diagnostic d = first_error(with_macros(*base, name, value), options);
      EXPECT_EQ(d.where.file, macro_at.file) << d.message;
      EXPECT_EQ(d.where.line, macro_at.line) << d.message;
      EXPECT_EQ(d.where.pointer, macro_at.pointer) << d.message;
      EXPECT_NE(d.message.find(said), std::string::npos) << d.message;
      EXPECT_NE(d.message.find("in the Macros entry '" + std::string(name) + "'"), std::string::npos)
          << d.message;
    }
    CompileOptions bad_global;
    bad_global.global_macros = {{"Y(", "1"}};
    ShaderDesc plain = *base;
    plain.where = shader_at;
    const Diagnostic d = first_error(plain, bad_global);
    EXPECT_EQ(d.where.pointer, shader_at.pointer) << d.message;
    EXPECT_NE(d.message.find("in -D Y("), std::string::npos) << d.message;
  }
  // A Macros entry that redefines one of the environment's names keeps the note saying where the other
  // definition comes from.
  const Diagnostic redefined = first_error(with_macros(glsl, "COMPUTE_SHADER", "2"), options);
  EXPECT_EQ(redefined.where.pointer, macro_at.pointer) << redefined.message;
  for (const char* said : {"Macro redefined", "(in the Macros entry 'COMPUTE_SHADER'",
                           "(statepack defines COMPUTE_SHADER before every shader"})
    EXPECT_NE(redefined.message.find(said), std::string::npos) << said << " not in " << redefined.message;

  ShaderDesc extensions = glsl;
  extensions.where = shader_at;
  extensions.glsl_extensions = "#extension GL_EXT_samplerless_texture_functions : enable\n#error here";
  extensions.extensions_where = extensions_at;
  const Diagnostic d = first_error(extensions, options);
  EXPECT_EQ(d.where.pointer, extensions_at.pointer) << d.message;
  EXPECT_NE(d.message.find("in GLSLExtensions"), std::string::npos) << d.message;
}

}  // namespace
}  // namespace statepack::packager
