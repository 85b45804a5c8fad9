struct VSOutput {
  float4 pos : SV_POSITION;
  float2 uv : TEXCOORD0;
};

VSOutput VSMain(uint id : SV_VertexID) {
  VSOutput o;
  float2 corner = float2((id << 1) & 2, id & 2);
  o.uv = corner;
  o.pos = float4(corner * float2(2, -2) + float2(-1, 1), 0, 1);
  return o;
}
