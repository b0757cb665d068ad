#version 430
// Direct-sum reference of the ocean fields (compute path, GL ≥ 4.3) — spec/000 §1.1(d), the
// O(n·m) summation the FFT replaces, spec/000 eq. 2.11 with the conjugate fixed.  Writes the
// same two field images as the FFT so ocean_finalize runs unchanged.  O(N²·modes): N ≤ 128
// only.
// Equations and guarded failure cases in direct_sum.glsl.
layout(local_size_x = 8, local_size_y = 8) in;
layout(rgba32f, binding = 0) writeonly uniform image2D uFields0;
layout(rgba32f, binding = 1) writeonly uniform image2D uFields1;

#include "direct_sum.glsl"

void main() {
    ivec2 texel = ivec2(gl_GlobalInvocationID.xy);
    if (texel.x >= uN || texel.y >= uN) return;
    vec4 fields0, fields1;
    DirectSumTexel(texel, fields0, fields1);
    imageStore(uFields0, texel, fields0);
    imageStore(uFields1, texel, fields1);
}
