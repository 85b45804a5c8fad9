#include "shade_common.hlsli"

cbuffer cbConstants : register(b0) {
  float4 g_Tint;
};
Texture2D g_Albedo : register(t0);
SamplerState g_Albedo_sampler : register(s0);

float4 PSMain(float4 pos : SV_POSITION, float2 uv : TEXCOORD0) : SV_TARGET {
  return shade(g_Albedo.Sample(g_Albedo_sampler, uv), g_Tint) * BRIGHTNESS;
}
