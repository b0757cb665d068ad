// Spectrum evolution of the Tessendorf ocean — spec/000 §1.1(d)–(e), spec/000 eq. 2.11 with the
// conjugate erratum fixed (Tessendorf 2001 eq. 26), and the packing of the eight field spectra
// into four complex numbers for the inverse FFT; one cascade (one band of |k|) per pass.
// h₀(k) is spec/000 eq. 2.10 as corrected in app/sim/ocean.py (factor ½, Ψ sampled at −k),
// computed on the CPU; ω(k) = sqrt(g·k·tanh(k·d)) (tanh, not the thesis's tan) in float64 on
// the CPU.  Numpy twin: app/sim/ocean.py (evolve_amplitudes, synthesize).  Shared by
// spectrum_evolve.comp/.frag and direct_sum.*.
//
//   h(k,t) = h₀(k)·e^{iωt} + conj(h₀(−k))·e^{−iωt}   (spec/000 eq. 2.11, conjugate restored)
//
// Field spectra (λ = choppiness, k = |k|; 1/k is 0 at k = 0):
//   F0 = h (η)            F1 = iλ(k_x/k)h (λD_x)      F2 = iλ(k_z/k)h (λD_z)
//   F3 = i k_x h (∂η/∂x)  F4 = i k_z h (∂η/∂z)        F5 = −λ(k_x²/k)h (λ∂D_x/∂x)
//   F6 = −λ(k_z²/k)h (λ∂D_z/∂z)                       F7 = −λ(k_x k_z/k)h (λ∂D_x/∂z)
// Each Fj is Hermitian (Fj(−k) = conj Fj(k)), so its transform fj is real, and the transform
// of A = F0 + i·F1 is f0 + i·f1 exactly: four complex FFTs give the eight real fields,
//   packed0 = (A, B) = (F0 + iF1, F2 + iF3),  packed1 = (C, D) = (F4 + iF5, F6 + iF7).
//
// Failure cases guarded:
// * k = 0: 1/k is taken as 0 (the mean level carries no displacement).
// * Nyquist row/column (index N/2): forced to zero — there k_x(−k) = k_x(k), so i·k·h would not
//   be Hermitian and the packing would leak imaginary parts between fields (numpy zeroes h₀
//   there too).
// * Phase at large t: ωt in float32 loses ~ωt·6e-8 rad (0.3 rad of jitter after a day for the
//   short waves).  ω/2π and t arrive split as hi + lo with 12-bit hi parts, so ν_hi·t_hi is exact
//   in float32 and is reduced with fract() before anything is added: the phase error stays near
//   ν·t·2⁻³⁶ cycles.  sin/cos then see an angle in [−π, π).

uniform sampler2D uH0;          // RGBA32F: (Re h₀(k), Im h₀(k), Re conj h₀(−k), Im conj h₀(−k))
uniform sampler2D uFrequency;   // RG32F: (ν_hi, ν_lo), ν = ω(k)/2π [cycles/s], float64 on the CPU
uniform sampler2D uWaveVector;  // RG32F: (k_x, k_z) [rad/m]
uniform vec2 uTime;             // (t_hi, t_lo) [s]
uniform float uChoppiness;      // λ
uniform int uN;

#include "fft_common.glsl"

const float OCEAN_TWO_PI = 6.283185307179586;

// e^{i·2π·ν·t} with ν = nu.x + nu.y and t = t.x + t.y (see "Phase at large t").
vec2 ExpTwoPiINuT(vec2 nu, vec2 t) {
    float cycles = fract(nu.x * t.x) + fract(nu.x * t.y) + fract(nu.y * t.x) + nu.y * t.y;
    cycles -= floor(cycles + 0.5);
    float angle = OCEAN_TWO_PI * cycles;
    return vec2(cos(angle), sin(angle));
}

// spec/000 eq. 2.11 (corrected, Tessendorf 2001 eq. 26): amp = (h₀(k), conj h₀(−k)),
// e = e^{iωt}.
vec2 EvolvedAmplitude(vec4 amp, vec2 e) {
    return ComplexMul(amp.xy, e) + ComplexMul(amp.zw, vec2(e.x, -e.y));
}

// 1/|k| (m) of a wave vector k (rad/m); 0 at k = 0 instead of an infinity (the mean mode).
float SafeInverseWavenumber(vec2 k) {
    float len = length(k);
    return len > 0.0 ? 1.0 / len : 0.0;
}

// i·z for a complex number z = (re, im).
vec2 TimesI(vec2 z) { return vec2(-z.y, z.x); }

// The four packed spectra A, B, C, D of one wave vector (see the header).
void PackFieldSpectra(vec2 h, vec2 k, float lambda, out vec4 packed0, out vec4 packed1) {
    float invK = SafeInverseWavenumber(k);
    vec2 ih = TimesI(h);
    vec2 f1 = lambda * k.x * invK * ih;
    vec2 f2 = lambda * k.y * invK * ih;
    vec2 f3 = k.x * ih;
    vec2 f4 = k.y * ih;
    vec2 f5 = -lambda * k.x * k.x * invK * h;
    vec2 f6 = -lambda * k.y * k.y * invK * h;
    vec2 f7 = -lambda * k.x * k.y * invK * h;
    packed0 = vec4(h + TimesI(f1), f2 + TimesI(f3));
    packed1 = vec4(f4 + TimesI(f5), f6 + TimesI(f7));
}

// Everything the evolve pass writes for one texel (k index = texel, numpy FFT order).
void EvolveSpectrumTexel(ivec2 texel, out vec4 packed0, out vec4 packed1) {
    if (texel.x == uN / 2 || texel.y == uN / 2) {  // Nyquist: zero (see the header)
        packed0 = vec4(0.0);
        packed1 = vec4(0.0);
        return;
    }
    vec4 amp = texelFetch(uH0, texel, 0);
    vec2 nu = texelFetch(uFrequency, texel, 0).xy;
    vec2 k = texelFetch(uWaveVector, texel, 0).xy;
    vec2 h = EvolvedAmplitude(amp, ExpTwoPiINuT(nu, uTime));
    PackFieldSpectra(h, k, uChoppiness, packed0, packed1);
}
