#version 450
// The source of compute_bytecode.spv, a module made outside statepack for the BYTECODE corpus file
// (tests/corpus/valid/bytecode.json).
// Rebuild it with glslang's command-line compiler:
//   glslangValidator -V --target-env vulkan1.0 -o compute_bytecode.spv compute_bytecode.comp
layout(local_size_x = 64) in;
layout(set = 0, binding = 0) buffer Values { uint values[]; };
layout(set = 0, binding = 1) uniform Params { uint count; uint scale; };
void main()
{
    uint i = gl_GlobalInvocationID.x;
    if (i < count) values[i] *= scale;
}
