// Types shared by the full-screen pass shaders (screen_tri.vsh and every .psh).
#ifndef STRUCTURES_FXH
#define STRUCTURES_FXH

// What the full-screen triangle hands to each pixel shader.
struct ScreenVSOutput
{
    float4 Pos : SV_Position; // pixel center in the PS: (i + 0.5, j + 0.5)
    float2 UV  : TEXCOORD0;   // (0,0) at the top-left corner, (1,1) at the bottom-right
};

// The G-buffer: four targets whose formats the application sets at run time.
struct GBufferOutput
{
    float4 Albedo    : SV_Target0; // RGBA8_UNORM
    float4 Normal    : SV_Target1; // RGBA8_UNORM, encoded with EncodeNormal
    float4 Emittance : SV_Target2; // R11G11B10_FLOAT: alpha is dropped
    float  Depth     : SV_Target3; // R32_FLOAT
};

#endif
