// Helpers shared by the G-buffer writer and the shading pass, so both agree on the encodings.
#ifndef ENCODING_FXH
#define ENCODING_FXH

// UNORM targets hold [0,1]: normals are stored as n * 0.5 + 0.5.
float3 EncodeNormal(float3 n)
{
    return n * 0.5 + 0.5;
}

float3 DecodeNormal(float3 e)
{
    return e * 2.0 - 1.0;
}

// Pixel position to [0,1] screen coordinates; InvSize is 1 / render-target size.
float2 PixelToScreenUV(float2 PixelPos, float2 InvSize)
{
    return PixelPos * InvSize;
}

#endif
