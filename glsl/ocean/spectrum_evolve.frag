#version 330 core
// Evolve pass of the FFT ocean (fragment path, GL 3.3): a full-screen pass writing the packed
// field spectra (A, B) and (C, D) of one cascade through MRT — spec/000 §1.1(d)–(e),
// spec/000 eq. 2.11 with the conjugate erratum fixed (Tessendorf 2001 eq. 26).  The equations,
// the packing and the guarded failure cases (k = 0, Nyquist, large t) are in
// spectrum_evolve.glsl.
layout(location = 0) out vec4 oPacked0;
layout(location = 1) out vec4 oPacked1;

#include "spectrum_evolve.glsl"

void main() {
    EvolveSpectrumTexel(ivec2(gl_FragCoord.xy), oPacked0, oPacked1);
}
