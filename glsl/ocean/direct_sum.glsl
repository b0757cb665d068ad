// Direct summation of the ocean fields over every non-zero mode — the O(n·m) method the thesis
// sets against the FFT (spec/000 §1.1(d): "summing about 10³ waves directly costs O(nm)"), the
// bench's reference for GpuFFT.  Same fields, same layout as the FFT's output
// (spectrum_evolve.glsl):  fields0 = (η, λD_x, λD_z, ∂η/∂x),
// fields1 = (∂η/∂z, λ∂D_x/∂x, λ∂D_z/∂z, λ∂D_x/∂z), from
//
//   c(k, x) = h(k,t)·e^{i k·x},  h(k,t) = h₀(k)e^{iωt} + conj h₀(−k)e^{−iωt}
//                                                             (spec/000 eq. 2.11, conjugate fixed)
//   η = Σ Re c,  λD_x = Σ −λ(k_x/k) Im c,  ∂η/∂x = Σ −k_x Im c,  λ∂D_x/∂x = Σ −λ(k_x²/k) Re c, …
//
// Cost O(N²·modes) per cascade: for N ≤ 128 (benches, tests) only.
// Failure cases guarded: k·x at grid point j is 2π·((m·j) mod N)/N, taken from an exact N-entry
// table by integer index (no float32 sin/cos of k·x); ωt as in spectrum_evolve.glsl; 1/k = 0
// at k = 0; Nyquist modes are left out of the mode list on the CPU, as the FFT path zeroes them.

uniform sampler2D uModes;       // RGBA32F; mode m at texels (3·(m mod W) + c, m div W):
                                //  c = 0: (h₀(k), conj h₀(−k)), c = 1: (k_x, k_z, ν_hi, ν_lo),
                                //  c = 2: (index x, index z, 0, 0) in numpy FFT order
uniform int uModeCount;
uniform int uModeWidth;         // W
uniform sampler2D uPhaseTable;  // N × 1 RG32F: e^{+2πi·q/N}

#include "spectrum_evolve.glsl"

// The two field texels (fields0, fields1, layout above; metres and slopes) at grid point
// `texel`, summed over all uModeCount modes of the mode texture: each mode's amplitude is
// evolved to uTime (spec/000 eq. 2.11) and turned by the exact phase e^{ik·x} from the table.
// Failure case: 1/k at k = 0 reads 0 (SafeInverseWavenumber): a k = 0 mode adds only to η.
void DirectSumTexel(ivec2 texel, out vec4 fields0, out vec4 fields1) {
    vec4 sumRe = vec4(0.0);  // weights of Re c: (η, λ∂D_x/∂x, λ∂D_z/∂z, λ∂D_x/∂z)
    vec4 sumIm = vec4(0.0);  // weights of Im c: (λD_x, λD_z, ∂η/∂x, ∂η/∂z)
    for (int m = 0; m < uModeCount; ++m) {
        ivec2 base = ivec2(3 * (m % uModeWidth), m / uModeWidth);
        vec4 amp = texelFetch(uModes, base, 0);
        vec4 wave = texelFetch(uModes, base + ivec2(1, 0), 0);
        ivec2 index = ivec2(texelFetch(uModes, base + ivec2(2, 0), 0).xy);
        int q = (index.x * texel.x + index.y * texel.y) & (uN - 1);
        vec2 c = ComplexMul(EvolvedAmplitude(amp, ExpTwoPiINuT(wave.zw, uTime)),
                            texelFetch(uPhaseTable, ivec2(q, 0), 0).xy);
        vec2 k = wave.xy;
        float invK = SafeInverseWavenumber(k);
        float lambda = uChoppiness;
        sumRe += c.x * vec4(1.0, -lambda * k.x * k.x * invK, -lambda * k.y * k.y * invK,
                            -lambda * k.x * k.y * invK);
        sumIm += c.y * vec4(-lambda * k.x * invK, -lambda * k.y * invK, -k.x, -k.y);
    }
    fields0 = vec4(sumRe.x, sumIm.x, sumIm.y, sumIm.z);
    fields1 = vec4(sumIm.w, sumRe.y, sumRe.z, sumRe.w);
}
