#version 330 core
// =============================================================================================
// Method 4, pass 2 — the multiple-scattering LUT Ψ_ms(h, μ_s) (Hillaire 2020 §5.5; 32 × 32,
// 64 directions in the paper). For a point at altitude h lit by a sun of zenith cosine μ_s and
// unit intensity, integrate over the sphere of directions ω (N × N stratified, uniform in cos θ
// and φ, weight 4π/N² each) with the isotropic phase p_u = 1/(4π) for both scattering events:
//
//   L_2nd   = ∫_Ω L'(x, −ω) p_u dω,                                  (Hillaire 2020 eq. 5)
//   L'(x,v) = ∫_0^{t_end} T(x, x+tv) σ_s(x+tv) p_u T_sun(x+tv) dt    (Hillaire 2020 eq. 6)
//             + T(x, x+t_g v) · (albedo/π) · max(μ_s,ground, 0) · T_sun,ground
//                                                                   (Hillaire 2020 eq. 7)
//   f_ms    = ∫_Ω [ ∫_0^{t_end} T(x, x+tv) σ_s(x+tv) dt ] p_u dω     (Hillaire 2020 eq. 8)
//   F_ms    = 1 + f_ms + f_ms² + … = 1/(1 − f_ms)                    (Hillaire 2020 eq. 9)
//   Ψ_ms    = L_2nd F_ms                                             (Hillaire 2020 eq. 10)
//
// Ψ_ms is per unit sun intensity; the sky-view, aerial-perspective and fallback marches add
// E_sun σ_s(x) Ψ_ms(h, μ_s) to the source term (Hillaire 2020 eq. 11). uHillaireMsInfinite = 0
// keeps only the second order (F_ms = 1). uHillaireGroundAlbedo is 0 by default: the thesis's
// model has no ground reflection, so method 4 differs from methods 1–3 by multiple scattering
// only.
// Output: rgb Ψ_ms, a = mean f_ms (a diagnostic).
//
// Failure cases: directions into the ground from h = 0 (empty segment, only the ground term),
// the sun below the horizon (planet shadow 0, Ψ comes from lit air elsewhere), f_ms → 1
// (clamped at 0.999; physically f_ms < 1 since ∫ T σ_s dt ≤ 1 − T_end).
// =============================================================================================
#include "hillaire_common.glsl"

in vec2 vUV;
out vec4 fragColor;
uniform vec2 uHillaireTargetSize;
uniform int uHillaireMsDirections;     // N: N² directions (8 → the paper's 64)
uniform int uHillaireMsSteps;          // samples per direction (the paper: 20)
uniform float uHillaireGroundAlbedo;   // Lambertian ground albedo in the LUT (0: none)
uniform float uHillaireMsInfinite;     // 1: F_ms = 1/(1 − f_ms); 0: second order only

// One texel (μ_s, h): the sphere of directions integrated as described above.
void main() {
    vec2 unit = floor(gl_FragCoord.xy) / max(uHillaireTargetSize - 1.0, vec2(1.0));
    float muS = ClampCosine(2.0 * unit.x - 1.0);
    float h = unit.y * HillaireAtmosphereHeight();
    float sinS = SafeSqrt(1.0 - muS * muS);
    int N = max(uHillaireMsDirections, 1);
    float fN = float(N);
    const float pu = 1.0 / (4.0 * PI);
    vec3 L2 = vec3(0.0);
    vec3 f = vec3(0.0);
    for (int j = 0; j < N; ++j) {
        float mu = 1.0 - 2.0 * (float(j) + 0.5) / fN;
        float sinT = SafeSqrt(1.0 - mu * mu);
        for (int i = 0; i < N; ++i) {
            float phi = TWO_PI * (float(i) + 0.5) / fN;
            float nu = mu * muS + sinT * sinS * cos(phi);
            vec2 seg = HillaireRaySegment(h, mu, HILLAIRE_INFINITY);
            vec3 Lp = vec3(0.0);
            if (seg.y > seg.x) {
                HillaireInScatter acc = HillaireIntegrateSegment(h, mu, muS, nu, seg.x, seg.y,
                                                                 uHillaireMsSteps, false);
                Lp = pu * (acc.rayleigh + acc.mie);
                f += acc.transfer;
                if (uHillaireGroundAlbedo > 0.0 && HillaireRayHitsGround(h, mu)) {
                    float tg = seg.y;
                    float r0 = uBottomRadius + h;
                    float muSG = ClampCosine((r0 * muS + tg * nu) / uBottomRadius);
                    vec3 sunG = HillaireSunTransmittanceAt(0.0, muSG);
                    Lp += exp(-acc.opticalDepth) * sunG * (uHillaireGroundAlbedo / PI)
                          * max(muSG, 0.0);
                }
            } else if (uHillaireGroundAlbedo > 0.0 && HillaireRayHitsGround(h, mu)) {
                vec3 sunG = HillaireSunTransmittanceAt(0.0, muS);
                Lp += sunG * (uHillaireGroundAlbedo / PI) * max(muS, 0.0);
            }
            L2 += Lp;
        }
    }
    // ∫ … p_u dω with dω = 4π/N²: the mean over the directions.
    float w = 1.0 / (fN * fN);
    L2 *= w;
    f *= w;
    vec3 Fms = uHillaireMsInfinite > 0.5 ? 1.0 / (1.0 - min(f, vec3(0.999))) : vec3(1.0);
    fragColor = vec4(L2 * Fms, HillaireMean(f));
}
