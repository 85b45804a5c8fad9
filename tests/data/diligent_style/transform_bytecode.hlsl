// The source of transform_bytecode.spv, a SPIR-V module made outside statepack (BYTECODE in the
// notation), as DXC or another toolchain would hand it over: the same transform as transform.vsh,
// spelled without Diligent's definitions. Rebuild it with glslang's command-line compiler:
//   glslangValidator -V -D -S vert -e main --hlsl-iomap -fhlsl_functionality1 \
//     -o transform_bytecode.spv transform_bytecode.hlsl
// tests/corpus/shaders/transform_bytecode.spv is a copy of that module (the corpus's BYTECODE case).
#pragma pack_matrix(row_major)

cbuffer Constants
{
    float4x4 g_Transform;
    float4 g_Scale;
};

struct VSInput
{
    float  Depth : ATTRIB1;
    float2 Pos   : ATTRIB0;
    float4 Color : ATTRIB2;
};

struct PSInput
{
    float4 Pos   : SV_POSITION;
    float4 Color : COLOR0;
    float2 UV    : TEX_COORD;
};

void main(in VSInput VSIn, out PSInput PSIn)
{
    float4x4 Scale = float4x4(float4(g_Scale.x, 0.0, 0.0, 0.0),
                              float4(0.0, g_Scale.y, 0.0, 0.0),
                              float4(0.0, 0.0, 1.0, 0.0),
                              float4(0.0, 0.0, 0.0, 1.0));
    PSIn.Pos = mul(mul(float4(VSIn.Pos, VSIn.Depth, 1.0), Scale), g_Transform);
    PSIn.Color = VSIn.Color;
    float2 NDC = PSIn.Pos.xy / PSIn.Pos.w;
    PSIn.UV = float2(0.5 + 0.5 * NDC.x, 0.5 - 0.5 * NDC.y);
    PSIn.Color.a = -2.0 * g_Transform[3][0];
}
