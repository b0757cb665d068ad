#version 430
// Evolve pass of the FFT ocean (compute path, GL ≥ 4.3): h(k,t) from h₀ and ω, and the eight
// field spectra packed into two RGBA32F images for GpuFFT — spec/000 §1.1(d)–(e),
// spec/000 eq. 2.11 with the conjugate erratum fixed (Tessendorf 2001 eq. 26), choppy
// displacement and spectral derivatives (§1.1(d) "Choppy", "Normals"), one dispatch per
// cascade (§1.1(e)).  The equations, the packing and the guarded failure cases (k = 0,
// Nyquist, large t) are in spectrum_evolve.glsl.
layout(local_size_x = 8, local_size_y = 8) in;
layout(rgba32f, binding = 0) writeonly uniform image2D uPacked0;  // (A, B)
layout(rgba32f, binding = 1) writeonly uniform image2D uPacked1;  // (C, D)

#include "spectrum_evolve.glsl"

void main() {
    ivec2 texel = ivec2(gl_GlobalInvocationID.xy);
    if (texel.x >= uN || texel.y >= uN) return;
    vec4 packed0, packed1;
    EvolveSpectrumTexel(texel, packed0, packed1);
    imageStore(uPacked0, texel, packed0);
    imageStore(uPacked1, texel, packed1);
}
