// Inline constants (tests/corpus/valid/inline_constants.json): the notation makes DrawConstants the
// pipeline's push constants; Material stays a uniform buffer.
cbuffer DrawConstants
{
    float4 g_Tint;
    float2 g_Offset;
};

cbuffer Material
{
    float4 g_Albedo;
};

float4 PSMain(float4 pos : SV_POSITION, float2 uv : TEXCOORD0) : SV_TARGET
{
    return g_Tint * g_Albedo + float4(uv + g_Offset, 0, 0);
}
