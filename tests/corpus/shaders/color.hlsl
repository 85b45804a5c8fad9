// The pixel shader of tests/corpus/valid/bytecode.json's graphics pipeline: the colour and v it is given.
float4 main(float4 pos : SV_POSITION, float4 color : COLOR0, float2 uv : TEX_COORD) : SV_TARGET
{
    return float4(color.rg, uv.y, color.a);
}
