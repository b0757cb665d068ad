// =============================================================================================
// Phase functions: how much of the light a particle scatters goes into each direction, per
// steradian, as a function of cos θ, θ the angle between the view ray (from the eye) and the
// direction toward the light (cos θ = 1: looking into the light). Each integrates to 1 over the
// sphere.
//
//   Henyey–Greenstein   (1 − g²) / (4π (1 + g² − 2g cos θ)^{3/2})            (spec/001 eq. 4.19,
//                                                                             spec/000 eq. 3.1)
//   Rayleigh            3/(16π) (1 + cos² θ)                                  (spec/002 §1.2)
//   Cornette–Shanks     3(1 − g²)(1 + cos² θ) / (8π (2 + g²)(1 + g² − 2g cos θ)^{3/2})
//                                                                            (spec/002 §1.2)
//
// Failure cases guarded: a cosine rounded past ±1 (clamped), g → ±1 (the denominator vanishes
// at cos θ = g: Henyey–Greenstein's is kept above 1e-6, Cornette–Shanks' g is clamped to
// |g| ≤ 0.9999; the CPU refuses |g| ≥ 1 for the atmosphere).
// Numpy twin: app/sim/optics.py (henyey_greenstein, phase_rayleigh, phase_mie_cornette_shanks).
// =============================================================================================
#include "math.glsl"

// spec/001 eq. 4.19 (the same function is spec/000 eq. 3.1), in 1/sr (g > 0 forward, g < 0
// backward scattering)
float HenyeyGreenstein(float cosTheta, float g) {
    float g2 = g * g;
    float denom = max(1.0 + g2 - 2.0 * g * ClampCosine(cosTheta), 1e-6);
    return (1.0 - g2) / (4.0 * PI * denom * sqrt(denom));
}

// Rayleigh scattering by molecules, in 1/sr
float PhaseRayleigh(float mu) { return 3.0 / (16.0 * PI) * (1.0 + mu * mu); }

// Cornette–Shanks phase for aerosols (Mie), in 1/sr; equals PhaseRayleigh at g = 0
float PhaseMieCornetteShanks(float mu, float g) {
    g = clamp(g, -0.9999, 0.9999);
    float g2 = g * g;
    float base = max(1.0 + g2 - 2.0 * g * mu, 1.0e-8);
    float denom = base * sqrt(base);   // base^1.5 without pow's log2/exp2
    return 1.0 / (4.0 * PI) * 3.0 * (1.0 - g2) / (2.0 * (2.0 + g2)) * (1.0 + mu * mu) / denom;
}
