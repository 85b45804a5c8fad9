// transform.vsh with Direct3D's semantics instead of ATTRIBn: InputLayout names them (HLSLSemantic), and
// each input reads the element of that semantic whose InputIndex is the semantic's index.
#include "transform_common.fxh"

struct VSInput
{
    float  Depth : DEPTH1;
    float4 Color : COLOR2;
    float2 Pos   : POSITION;
};

void main(in VSInput VSIn, out PSInput PSIn)
{
    Transform(VSIn.Pos, VSIn.Depth, VSIn.Color, PSIn);
}
