// A transform written as Diligent's tutorials write theirs, for tests/gl/diligent_style_test.cpp: a
// row-vector matrix the application uploads row by row (PACK_MATRIX_ROW_MAJOR), vertex inputs named
// ATTRIBn and declared out of order, and the engine's definitions (MatrixFromRows, MATRIX_ELEMENT,
// NormalizedDeviceXYToTexUV), which no line of this file defines.
cbuffer Constants
{
    float4x4 g_Transform;  // clip = mul(float4(position, 1), g_Transform)
    float4 g_Scale;        // x and y scale, applied first
};

struct VSInput
{
    float4 Color : ATTRIB2;
    float2 Pos   : ATTRIB0;
    float  Depth : ATTRIB1;
};

struct PSInput
{
    float4 Pos   : SV_POSITION;
    float4 Color : COLOR0;
    float2 UV    : TEX_COORD;
};

void main(in VSInput VSIn, out PSInput PSIn)
{
    float4x4 Scale = MatrixFromRows(float4(g_Scale.x, 0.0, 0.0, 0.0),
                                    float4(0.0, g_Scale.y, 0.0, 0.0),
                                    float4(0.0, 0.0, 1.0, 0.0),
                                    float4(0.0, 0.0, 0.0, 1.0));
    PSIn.Pos = mul(mul(float4(VSIn.Pos, VSIn.Depth, 1.0), Scale), g_Transform);
    PSIn.Color = VSIn.Color;
    // Where this vertex lands in a texture of the target: v runs down the image.
    PSIn.UV = NormalizedDeviceXYToTexUV(PSIn.Pos.xy / PSIn.Pos.w);
#if !defined(VERTEX_SHADER) || !defined(GLSLANG) || !defined(VULKAN) || !defined(HLSL)
    PSIn.Color = float4(1.0, 0.0, 1.0, 1.0);  // an environment unlike Diligent's: a colour the test refuses
#endif
    // MATRIX_ELEMENT reads row 3 (the translation of a row-vector matrix), column 0: -1 in the test.
    PSIn.Color.a = -2.0 * MATRIX_ELEMENT(g_Transform, 3, 0);
}
