// A triangle over the whole target, from SV_VertexID (no vertex buffer).
float4 main(in uint VertId : SV_VertexID) : SV_POSITION
{
    float2 UV = float2((VertId << 1) & 2, VertId & 2);
    return float4(TexUVToNormalizedDeviceXY(UV), 0.0, 1.0);
}
