// DXC's spelling of a push constant, which glslang turns into a $Global uniform member.
struct DrawConstants {
  float4 tint;
};
[[vk::push_constant]] DrawConstants g_Draw;

float4 main() : SV_TARGET {
  return g_Draw.tint;
}
