// A push-constant cbuffer: its members are globals of the shader.
[[vk::push_constant]] cbuffer FillConstants {
  uint g_Count;
  float g_Value;
};
RWStructuredBuffer<float> g_Output : register(u0);

[numthreads(64, 1, 1)] void main(uint3 id : SV_DispatchThreadID) {
  if (id.x < g_Count) g_Output[id.x] = g_Value;
}
