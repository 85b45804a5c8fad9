// statepack's HLSL environment: the names Diligent Engine defines before every HLSL shader it compiles
// for Vulkan, so that Diligent's own shaders (its tutorials, DiligentFX) compile unchanged. Written for
// statepack from what each name does; docs/notation.md ("The shader environment") lists them.
//
// statepack puts this text in glslang's preamble, after `#define GLSLANG` and before the stage macro
// (VERTEX_SHADER, PIXEL_SHADER, ...), the -D macros and the shader's own Macros. Every value follows
// Diligent's Vulkan conventions: clip-space depth runs 0..1, and clip-space y points up as in Direct3D,
// because Diligent's Vulkan backend flips the viewport (a negative height); an application using these
// shaders does the same.
#ifndef STATEPACK_DILIGENT_HLSL_ENVIRONMENT
#define STATEPACK_DILIGENT_HLSL_ENVIRONMENT

// Shaders shared between languages test this to pick their HLSL spelling.
#define HLSL

// The smallest depth of normalized device space: 0 on Vulkan (OpenGL without clip control has -1).
#define NDC_MIN_Z 0.0

// Multiplies normalized device x, y, z into texture u, v and depth (after adding 0.5 to u and v):
// v runs down the texture while y runs up, and depth is z itself.
#define F3NDC_XYZ_TO_UVD_SCALE float3(0.5, -0.5, 1.0)

// Normalized device x, y (-1..1, y up) to texture coordinates (0..1, v down), and back.
float2 NormalizedDeviceXYToTexUV(float2 ndc_xy)
{
    return float2(0.5 + 0.5 * ndc_xy.x, 0.5 - 0.5 * ndc_xy.y);
}
float2 TexUVToNormalizedDeviceXY(float2 uv)
{
    return float2(2.0 * uv.x - 1.0, 1.0 - 2.0 * uv.y);
}

// Normalized device z to the depth a depth buffer stores, and back: the same number when z runs 0..1.
float NormalizedDeviceZToDepth(float ndc_z)
{
    return ndc_z;
}
float DepthToNormalizedDeviceZ(float depth)
{
    return depth;
}

// Comparisons and logic as functions, so that one spelling serves HLSL and GLSL (whose vector
// comparisons are functions). Each argument is parenthesised, as operator precedence needs.
#define Less(a, b)         ((a) < (b))
#define LessEqual(a, b)    ((a) <= (b))
#define Greater(a, b)      ((a) > (b))
#define GreaterEqual(a, b) ((a) >= (b))
#define Equal(a, b)        ((a) == (b))
#define NotEqual(a, b)     ((a) != (b))
#define Not(a)             (!(a))
#define And(a, b)          ((a) && (b))
#define Or(a, b)           ((a) || (b))

// 1.0 for each true component, 0.0 for each false one.
float BoolToFloat(bool value)
{
    return value ? 1.0 : 0.0;
}
float2 BoolToFloat(bool2 value)
{
    return float2(BoolToFloat(value.x), BoolToFloat(value.y));
}
float3 BoolToFloat(bool3 value)
{
    return float3(BoolToFloat(value.x), BoolToFloat(value.y), BoolToFloat(value.z));
}
float4 BoolToFloat(bool4 value)
{
    return float4(BoolToFloat(value.x), BoolToFloat(value.y), BoolToFloat(value.z), BoolToFloat(value.w));
}

// The element in row `row`, column `col` of a matrix (HLSL indexes rows first; GLSL columns first).
#define MATRIX_ELEMENT(matrix, row, col) matrix[row][col]

// A matrix whose rows are the given vectors (HLSL's constructors take rows; GLSL's take columns).
float2x2 MatrixFromRows(float2 first, float2 second)
{
    return float2x2(first, second);
}
float3x3 MatrixFromRows(float3 first, float3 second, float3 third)
{
    return float3x3(first, second, third);
}
float4x4 MatrixFromRows(float4 first, float4 second, float4 third, float4 fourth)
{
    return float4x4(first, second, third, fourth);
}

// A storage image's format attribute, which only DXC reads: nothing for glslang.
#define VK_IMAGE_FORMAT(format)

#endif
