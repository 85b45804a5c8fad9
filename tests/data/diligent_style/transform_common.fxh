// transform.vsh's body, shared with the shaders that read their inputs another way.
cbuffer Constants
{
    float4x4 g_Transform;
    float4 g_Scale;
};

struct PSInput
{
    float4 Pos   : SV_POSITION;
    float4 Color : COLOR0;
    float2 UV    : TEX_COORD;
};

void Transform(float2 Pos, float Depth, float4 Color, out PSInput PSIn)
{
    float4x4 Scale = MatrixFromRows(float4(g_Scale.x, 0.0, 0.0, 0.0),
                                    float4(0.0, g_Scale.y, 0.0, 0.0),
                                    float4(0.0, 0.0, 1.0, 0.0),
                                    float4(0.0, 0.0, 0.0, 1.0));
    PSIn.Pos = mul(mul(float4(Pos, Depth, 1.0), Scale), g_Transform);
    PSIn.Color = Color;
    PSIn.UV = NormalizedDeviceXYToTexUV(PSIn.Pos.xy / PSIn.Pos.w);
    PSIn.Color.a = -2.0 * MATRIX_ELEMENT(g_Transform, 3, 0);
}
