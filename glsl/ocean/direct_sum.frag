#version 330 core
// Direct-sum reference of the ocean fields (fragment path, GL 3.3) — spec/000 §1.1(d), the
// O(n·m) summation the FFT replaces, spec/000 eq. 2.11 with the conjugate fixed.  Writes the
// same two field textures as the FFT (MRT) so ocean_finalize runs unchanged.  O(N²·modes):
// N ≤ 128 only.  Equations and guarded failure cases in direct_sum.glsl.
layout(location = 0) out vec4 oFields0;
layout(location = 1) out vec4 oFields1;

#include "direct_sum.glsl"

void main() {
    DirectSumTexel(ivec2(gl_FragCoord.xy), oFields0, oFields1);
}
