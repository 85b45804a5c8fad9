// Owen-scrambled 2-D Sobol points with hash-based scrambling (Burley 2020, "Practical Hash-based Owen
// Scrambling", JCGT 9(4); the hash is Vegdahl's 2021 improvement of Laine and Karras's 2011 one).
// The CPU computes the same bits (samples/path_tracer/sobol.hpp; tests/samples/rng_test.cpp checks it).
#ifndef PATH_TRACER_SOBOL_GLSL
#define PATH_TRACER_SOBOL_GLSL

// A bijection of 32-bit words in which output bit b is input bit b flipped by a function of the bits
// below it and the seed (additions, odd multiplications and x ^= x * even only carry upwards). On
// bit-reversed fixed-point numbers that is a nested uniform (Owen) scramble: each digit is flipped by a
// random function of the more significant digits, which keeps every (0,m,2)-net a net.
uint owen_hash(uint x, uint seed) {
  x ^= x * 0x3d20adeau;
  x += seed;
  x *= (seed >> 16u) | 1u;
  x ^= x * 0x05526c56u;
  x ^= x * 0x53a22864u;
  return x;
}

// The first two Sobol dimensions of `index`, bit-reversed (the point's first binary digit in bit 0).
// Dimension 0 (van der Corput) reversed is the index itself; dimension 1's generator matrix comes from
// the polynomial x + 1: direction number i is v(i-1) ^ (v(i-1) >> 1), i.e. r ^ (r << 1) reversed.
uvec2 sobol_reversed(uint index) {
  uint y = 0u, r = 1u;
  for (uint i = index; i != 0u; i >>= 1u, r ^= r << 1u)
    if ((i & 1u) != 0u) y ^= r;
  return uvec2(index, y);
}

// Point `index` of the scrambled sequence with seeds (shuffle, scramble x, scramble y), as 32-bit
// fractions. The index is shuffled by the same scramble on its reversed bits, which permutes indices
// inside every aligned block of 2^k: the first 2^k samples are still one aligned block of the Sobol
// sequence, a (0,k,2)-net, so every prefix stays well distributed (the window accumulates).
uvec2 scrambled_sobol(uint index, uvec3 seeds) {
  uint shuffled = bitfieldReverse(owen_hash(bitfieldReverse(index), seeds.x));
  uvec2 p = sobol_reversed(shuffled);
  return uvec2(bitfieldReverse(owen_hash(p.x, seeds.y)), bitfieldReverse(owen_hash(p.y, seeds.z)));
}

#endif
