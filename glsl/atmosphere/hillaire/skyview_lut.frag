#version 330 core
// =============================================================================================
// Method 4, pass 3 — the sky-view LUT, when the camera's altitude or the sun's elevation changed
// (Hillaire 2020 §5.3; the paper builds it every frame). For each (θ, φ) texel
// (skyview.glsl), integrate the view ray from the camera (or from the atmosphere's entry point
// when the camera is above the top, §6) to the top or the ground:
//
//   L = E_sun ∫ T_view [ T_sun (σ_R P_R(ν) + σ_M P_M(ν)) + σ_s Ψ_ms ] dt
//                                            (Hillaire 2020 eq. 1, Hillaire 2020 eq. 11)
//
// Target 0: rgb = P_R(ν) ∫T T_sun σ_R + ∫T σ_s Ψ_ms (per unit E_sun), a = ∫ρ_R dt;
// target 1: rgb = ∫T T_sun σ_M (no phase), a = ∫ρ_M dt — the lookup multiplies by P_M(ν) of the
// pixel, so the Mie halo stays as sharp as G makes it, and takes the ray's per-channel
// transmittance from the two density integrals. Sun disk not included (the scene adds it).
// uHillaireSkyViewSteps samples, dense at low altitudes (hillaire_common.glsl).
//
// Failure cases: rays that miss the atmosphere from space (0, T = 1); the sun at the zenith
// (φ meaningless: every column is the same); ground rays from h = 0 (empty segment).
// =============================================================================================
#include "hillaire_common.glsl"
#include "skyview.glsl"

in vec2 vUV;
layout(location = 0) out vec4 outRayleighMultiple;
layout(location = 1) out vec4 outMie;
uniform vec2 uHillaireTargetSize;
uniform int uHillaireSkyViewSteps;

// One texel: the ray of its (zenith, azimuth) angles from the camera's altitude, integrated to the
// top or the ground; rgb phased Rayleigh + multiple and phase-free Mie, alphas ∫ρ_R dt, ∫ρ_M dt.
void main() {
    float h0 = uHillaireCameraHeight;
    vec2 angles = HillaireSkyViewAngles(ivec2(gl_FragCoord.xy), ivec2(uHillaireTargetSize), h0);
    float mu = cos(angles.x);
    float sinT = sin(angles.x);
    vec3 up = CameraUp();
    float muS = ClampCosine(dot(uSunDir, up));
    float nu = ClampCosine(mu * muS + sinT * SafeSqrt(1.0 - muS * muS) * cos(angles.y));
    vec2 seg = HillaireRaySegment(h0, mu, HILLAIRE_INFINITY);
    HillaireInScatter acc = HillaireIntegrateSegment(h0, mu, muS, nu, max(seg.x, 0.0), seg.y,
                                                     uHillaireSkyViewSteps, true);
    outRayleighMultiple = vec4(PhaseRayleigh(nu) * acc.rayleigh + acc.multiple, acc.density.x);
    outMie = vec4(acc.mie, acc.density.y);
}
