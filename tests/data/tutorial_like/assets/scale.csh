// Fills g_Values[i] = i * g_Multiplier + VALUE_OFFSET for i < g_Count.
static const uint VALUE_OFFSET = 3;

cbuffer cbScaleConstants
{
    uint  g_Count;
    uint  g_Multiplier;
    uint2 g_Padding; // keeps the block 16 bytes
}

RWStructuredBuffer<uint> g_Values;

[numthreads(64, 1, 1)]
void main(uint3 ThreadId : SV_DispatchThreadID)
{
    // The last group may run past the end: the dispatch is rounded up to 64.
    if (ThreadId.x < g_Count)
        g_Values[ThreadId.x] = ThreadId.x * g_Multiplier + VALUE_OFFSET;
}
