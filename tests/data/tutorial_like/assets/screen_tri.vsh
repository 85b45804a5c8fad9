#include "structures.fxh"

// One triangle that covers the whole viewport, made from the vertex index alone
// (no vertex buffers): ids 0, 1, 2 give UV (0,0), (2,0), (0,2).
void main(in uint VertId : SV_VertexID, out ScreenVSOutput VSOut)
{
    float2 UV = float2((VertId << 1u) & 2u, VertId & 2u);
    VSOut.UV  = UV;
    // Vulkan's NDC has y pointing down, so UV.y = 0 is the top row.
    VSOut.Pos = float4(UV * 2.0 - 1.0, 0.0, 1.0);
}
