#include "include_error_common.hlsli"

float4 main() : SV_TARGET { return scaled(1.0); }
