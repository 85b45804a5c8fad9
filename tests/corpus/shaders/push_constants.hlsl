// HLSL push constants in the two spellings glslang makes push-constant blocks of (docs/notation.md).
struct DrawConstants {
  float4 offset_scale;  // xy offset, zw scale
  float4 tint;
};
[[vk::push_constant]] ConstantBuffer<DrawConstants> g_Draw;

struct VSOutput {
  float4 pos : SV_POSITION;
  float2 uv : TEXCOORD0;
};

VSOutput VSMain(uint id : SV_VertexID) {
  VSOutput o;
  float2 corner = float2((id << 1) & 2, id & 2);
  o.uv = corner;
  o.pos = float4(corner * g_Draw.offset_scale.zw + g_Draw.offset_scale.xy, 0, 1);
  return o;
}

float4 PSMain(VSOutput input) : SV_TARGET {
  return g_Draw.tint * float4(input.uv, 0, 1);
}
