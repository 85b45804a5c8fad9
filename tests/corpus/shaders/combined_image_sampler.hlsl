// DXC's [[vk::combinedImageSampler]]: each Texture2D/SamplerState pair declared with it at one binding
// is one combined image sampler descriptor (bindings 0 and 2); the unattributed pair at t1/s1 stays two
// descriptors, as HLSL registers always do.
#include "combined_common.hlsli"

[[vk::combinedImageSampler]]
[[vk::binding(0, 0)]]
Texture2D albedo;
[[vk::combinedImageSampler]] [[vk::binding(0, 0)]] SamplerState albedoSampler;

Texture2D plain : register(t1);
SamplerState plainSampler : register(s1);

float4 PSMain(float4 pos : SV_POSITION, float2 uv : TEXCOORD0) : SV_Target {
  return albedo.Sample(albedoSampler, uv) * detail.Sample(detailSampler, uv * 4) + plain.Sample(plainSampler, uv);
}
