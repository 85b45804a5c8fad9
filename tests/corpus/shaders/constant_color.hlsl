// A pixel shader that needs nothing: white.
float4 main() : SV_TARGET
{
    return float4(1.0, 1.0, 1.0, 1.0);
}
