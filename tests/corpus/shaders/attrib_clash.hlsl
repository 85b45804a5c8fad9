// Two vertex inputs that read one location once ATTRIBn places them (tests/corpus/invalid).
float4 main(float3 Pos : ATTRIB1, float3 Normal : TEXCOORD0, float2 UV : ATTRIB0) : SV_POSITION
{
    return float4(Pos + Normal, UV.x);
}
