#version 330 core
// One radix-2 Stockham stage of the inverse FFT, as a full-screen pass over FFT_COUNT N×N
// RGBA32F textures at once (MRT) — the fragment path of GpuFFT (app/gpu/fft.py) for GL 3.3,
// where compute shaders are missing (macOS stops at 4.1).  Spec/000 §1.1(d) (Tessendorf 2001,
// §3.1; Cooley–Tukey 1965; Stockham autosort as in Govindaraju et al. 2008).
//
//   out[m] = Σ_k in[k]·e^{+2πi·k·m/N}     along x (uAxis = 0) or z (uAxis = 1)
//
// Stage with span Ns = 1, 2, …, N/2: for j < N/2, k = j mod Ns, w = e^{+2πi·k/(2Ns)},
//   dst[(j div Ns)·2Ns + k]      = src[j] + w·src[j + N/2]
//   dst[(j div Ns)·2Ns + k + Ns] = src[j] − w·src[j + N/2]
// written output-first: each fragment finds its j and its sign.  log2 N passes per axis,
// ping-ponging; no bit reversal is needed (autosort).  2·log2 N passes in all — an even
// number, so the result lands back in the textures the data started in.
//
// Defines: FFT_COUNT (1…8 textures per pass).
// Failure cases guarded: twiddles from a float64 table (no sin/cos of large float32 angles);
// exact integer indexing with texelFetch (no filtering, no half-texel offsets).
#ifndef FFT_COUNT
#define FFT_COUNT 1
#endif

uniform sampler2D uTwiddle;  // N/2 × 1, RG32F: e^{+2πi·m/N}, m < N/2
uniform int uN;
uniform int uAxis;
uniform int uSpan;           // Ns

uniform sampler2D uSrc0;
layout(location = 0) out vec4 oDst0;
#if FFT_COUNT > 1
uniform sampler2D uSrc1;
layout(location = 1) out vec4 oDst1;
#endif
#if FFT_COUNT > 2
uniform sampler2D uSrc2;
layout(location = 2) out vec4 oDst2;
#endif
#if FFT_COUNT > 3
uniform sampler2D uSrc3;
layout(location = 3) out vec4 oDst3;
#endif
#if FFT_COUNT > 4
uniform sampler2D uSrc4;
layout(location = 4) out vec4 oDst4;
#endif
#if FFT_COUNT > 5
uniform sampler2D uSrc5;
layout(location = 5) out vec4 oDst5;
#endif
#if FFT_COUNT > 6
uniform sampler2D uSrc6;
layout(location = 6) out vec4 oDst6;
#endif
#if FFT_COUNT > 7
uniform sampler2D uSrc7;
layout(location = 7) out vec4 oDst7;
#endif

#include "fft_common.glsl"

vec4 StockhamButterfly(sampler2D src, ivec2 texelA, ivec2 texelB, vec2 signedTwiddle) {
    return texelFetch(src, texelA, 0) + ComplexMulPair(texelFetch(src, texelB, 0), signedTwiddle);
}

void main() {
    ivec2 texel = ivec2(gl_FragCoord.xy);
    int o = uAxis == 0 ? texel.x : texel.y;
    int span2 = 2 * uSpan;
    int block = o / span2;
    int r = o - block * span2;
    bool upper = r >= uSpan;
    int k = upper ? r - uSpan : r;
    int j = block * uSpan + k;
    ivec2 texelA = uAxis == 0 ? ivec2(j, texel.y) : ivec2(texel.x, j);
    ivec2 texelB = uAxis == 0 ? ivec2(j + uN / 2, texel.y) : ivec2(texel.x, j + uN / 2);
    vec2 w = texelFetch(uTwiddle, ivec2(k * (uN / span2), 0), 0).xy;
    w = upper ? -w : w;  // a − w·b = a + (−w)·b exactly
    oDst0 = StockhamButterfly(uSrc0, texelA, texelB, w);
#if FFT_COUNT > 1
    oDst1 = StockhamButterfly(uSrc1, texelA, texelB, w);
#endif
#if FFT_COUNT > 2
    oDst2 = StockhamButterfly(uSrc2, texelA, texelB, w);
#endif
#if FFT_COUNT > 3
    oDst3 = StockhamButterfly(uSrc3, texelA, texelB, w);
#endif
#if FFT_COUNT > 4
    oDst4 = StockhamButterfly(uSrc4, texelA, texelB, w);
#endif
#if FFT_COUNT > 5
    oDst5 = StockhamButterfly(uSrc5, texelA, texelB, w);
#endif
#if FFT_COUNT > 6
    oDst6 = StockhamButterfly(uSrc6, texelA, texelB, w);
#endif
#if FFT_COUNT > 7
    oDst7 = StockhamButterfly(uSrc7, texelA, texelB, w);
#endif
}
