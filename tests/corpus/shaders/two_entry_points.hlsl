// One HLSL file, two entry points with disjoint resources: each entry point's layout holds only what
// it statically uses (glslang keeps every global; statepack removes the unused ones before reflection).
cbuffer VSConstants {
  float4x4 g_Transform;
};
Texture2D g_Texture;
SamplerState g_Texture_sampler;

struct VSOut {
  float4 pos : SV_Position;
  float2 uv : TEXCOORD0;
};

VSOut VSMain(uint id : SV_VertexID) {
  VSOut o;
  o.uv = float2(id & 1, id >> 1);
  o.pos = mul(g_Transform, float4(o.uv, 0, 1));
  return o;
}

float4 PSMain(VSOut i) : SV_Target {
  return g_Texture.Sample(g_Texture_sampler, i.uv);
}
