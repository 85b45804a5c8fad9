// A 3-tap horizontal blur of one row, from one buffer into another.
StructuredBuffer<float> source : register(t0);
RWStructuredBuffer<float> blurred : register(u0);
[numthreads(64, 1, 1)]
void main(uint3 id : SV_DispatchThreadID) {
  uint count, stride;
  source.GetDimensions(count, stride);
  if (id.x >= count) return;
  float left = source[max(id.x, 1) - 1], right = source[min(id.x + 1, count - 1)];
  blurred[id.x] = (left + source[id.x] + right) / 3.0;
}
