// Every definition of Diligent's shader environment, evaluated: tests/gl/diligent_style_test.cpp
// compares each value with what the name means (docs/notation.md, "The shader environment").
RWStructuredBuffer<float> g_Values;

[numthreads(1, 1, 1)]
void main()
{
    uint i = 0;
    float2 uv = NormalizedDeviceXYToTexUV(float2(-0.5, 0.25));
    g_Values[i++] = uv.x;
    g_Values[i++] = uv.y;
    float2 ndc = TexUVToNormalizedDeviceXY(float2(0.25, 0.75));
    g_Values[i++] = ndc.x;
    g_Values[i++] = ndc.y;
    g_Values[i++] = NormalizedDeviceZToDepth(0.375);
    g_Values[i++] = DepthToNormalizedDeviceZ(0.625);
    g_Values[i++] = NDC_MIN_Z;
    float3 uvd = F3NDC_XYZ_TO_UVD_SCALE;
    g_Values[i++] = uvd.x;
    g_Values[i++] = uvd.y;
    g_Values[i++] = uvd.z;
    g_Values[i++] = Less(1.0, 2.0) ? 1.0 : 0.0;
    g_Values[i++] = LessEqual(2.0, 2.0) ? 1.0 : 0.0;
    g_Values[i++] = Greater(1.0, 2.0) ? 1.0 : 0.0;
    g_Values[i++] = GreaterEqual(1.0, 2.0) ? 1.0 : 0.0;
    g_Values[i++] = Equal(3, 3) ? 1.0 : 0.0;
    g_Values[i++] = NotEqual(3, 3) ? 1.0 : 0.0;
    g_Values[i++] = Not(false) ? 1.0 : 0.0;
    g_Values[i++] = And(true, false) ? 1.0 : 0.0;
    g_Values[i++] = Or(true, false) ? 1.0 : 0.0;
    float4 b4 = BoolToFloat(bool4(true, false, false, true));
    g_Values[i++] = b4.x + 2.0 * b4.y + 4.0 * b4.z + 8.0 * b4.w;
    g_Values[i++] = BoolToFloat(true) + BoolToFloat(bool2(false, true)).y + BoolToFloat(bool3(true, true, false)).z;
    // A matrix whose rows are (1 2 3 4), (5 6 7 8), ...: MATRIX_ELEMENT(m, row, col).
    float4x4 m = MatrixFromRows(float4(1, 2, 3, 4), float4(5, 6, 7, 8), float4(9, 10, 11, 12), float4(13, 14, 15, 16));
    g_Values[i++] = MATRIX_ELEMENT(m, 1, 2);
    g_Values[i++] = MATRIX_ELEMENT(m, 3, 0);
    float3x3 m3 = MatrixFromRows(float3(1, 2, 3), float3(4, 5, 6), float3(7, 8, 9));
    g_Values[i++] = mul(float3(1, 0, 0), m3).y;  // a row vector times the matrix: row 0, column 1
    float2x2 m2 = MatrixFromRows(float2(1, 2), float2(3, 4));
    g_Values[i++] = mul(m2, float2(0, 1)).x;      // the matrix times a column vector: row 0, column 1
    // The stage and compiler macros.
#if defined(COMPUTE_SHADER) && COMPUTE_SHADER == 1 && defined(GLSLANG) && defined(HLSL) && defined(VULKAN) && !defined(VERTEX_SHADER) && !defined(PIXEL_SHADER)
    g_Values[i++] = 1.0;
#else
    g_Values[i++] = 0.0;
#endif
}
