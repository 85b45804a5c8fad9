float4 shade(float4 albedo, float4 tint) { return albedo * tint; }
