// Vertex inputs named ATTRIBn and not (tests/corpus/warnings/diligent_warnings.json).
float4 main(float3 Pos : ATTRIB0, float2 UV : TEXCOORD0) : SV_POSITION
{
    return float4(Pos, UV.x);
}
