// =============================================================================================
// Method 4 — beyond the thesis: Hillaire's LUT atmosphere, shared part.
// S. Hillaire, "A Scalable and Production Ready Sky and Atmosphere Rendering Technique",
// EGSR 2020 (Computer Graphics Forum 39(4)). Same physical model and constants as the thesis's
// three methods (spec/002 §1, §7; glsl/atmosphere/model.glsl): Rayleigh + Mie with exponential
// density ρ_x(h) = P0·exp(−h/H_x), β^ext_M = 1.1 β^scatt_M, Cornette–Shanks phase, and — beyond
// the thesis, off by default — model.glsl's ozone layer, which adds σ_a ρ_O(h) to the extinction
// of every view ray and of the transmittance LUT (absorption only: no scattering term).
//
// What this file holds, used by every Hillaire pass and by hillaire_lookup.glsl:
//
//   * the (h, μ) geometry of a ray leaving altitude h with zenith cosine μ, written in the
//     cancellation-free forms float32 needs at planet scale (R ≈ 6.4·10⁶ m: r² ≈ 4·10¹³ has an
//     ulp of 4·10⁶ m², so r² − R² must never be formed directly):
//         r(t)        = sqrt(r² + 2 r μ t + t²),  h(t) = h + (t² + 2 r μ t)/(r(t) + r)
//         μ_s(t)      = (r μ_s + t ν)/r(t)      (ν = cos of the view–sun angle, constant on a ray)
//         ρ(h)        = sqrt(r² − R²) = sqrt(h (2R + h))
//         d_top(h, μ) = distance to the top sphere; d_ground(h, μ) = ρ² / (−rμ + sqrt(r²μ² − ρ²))
//   * the transmittance LUT parametrisation (Hillaire §4 uses Bruneton & Neyret 2008 / Bruneton
//     2017's): x_r = ρ/H_top, x_μ = (d − d_min)/(d_max − d_min), d_min = r_top − r,
//     d_max = ρ + H_top, H_top = sqrt(r_top² − R²); it covers every ray that does not hit the
//     ground, so sun transmittance = LUT × (sun above the local horizon)
//     (Hillaire 2020 §4, Hillaire 2020 eq. 1);
//   * the multiple-scattering LUT lookup Ψ_ms(h, μ_s) (Hillaire 2020 §5.5; the LUT itself is
//     built, equation by equation, in multiscattering_lut.frag);
//   * the view-ray integrator shared by the sky-view, aerial-perspective and fallback marches:
//         L(ν) = E_sun ∫ T_view(t) [ T_sun(t) (σ_R(t) P_R(ν) + σ_M(t) P_M(ν)) + σ_s(t) Ψ_ms(t) ] dt
//     (Hillaire 2020 eq. 1 with S = single + multiple, Hillaire 2020 eq. 11), where
//     E_sun = uSunIntensity — the thesis's "lightSun", which plays the role of a sun
//     *illuminance*: phase functions are per steradian, so E·σ·p is a radiance per metre. The
//     single-scattering part is exactly the integral of the thesis's method 1 (spec/002 §1.5)
//     with V ≡ 1.
//     The integrator returns the Rayleigh and Mie integrals *without* their phase functions:
//     ν is constant along a ray, so the phase is applied per pixel by the lookup, exactly —
//     the sharp Mie halo (G = 0.76) never goes through a LUT's bilinear filter.
//
// Sample placement: midpoint sums in s ∈ (0, 1) with t = a + L s² (dense at the low end of each
// monotone-altitude piece: the ray is split at its perigee t_p = −rμ, half the samples on each
// side). Numerically (numpy, 30 steps, 120 rays from the ground to 600 km) the max error is
// 0.8 % of the peak channel, where uniform steps give 9 % (vertical Mie at the ground); rays
// grazing the ground from altitude (perigee within a few hundred metres) reach 2.5 % (splitting
// by length instead of in halves: 30 %). The transmittance LUT uses t = d s³
// (40 samples: ≤ 2·10⁻⁵ relative in optical depth, Hillaire uses 40 uniform ones).
//
// Failure cases guarded: μ outside [−1, 1] (ClampCosine), sqrt of rounding negatives (SafeSqrt),
// rays starting above the top (moved to the entry point, Hillaire §6 "space views"), rays that
// miss the atmosphere (empty segment), the sun below the local horizon (planet shadow: 0),
// h < 0 (clamped), zero-length segments, f_ms → 1 (clamped denominator).
// =============================================================================================
#include "../model.glsl"

uniform sampler2D uHillaireTransmittanceLut;   // rgb: transmittance to the top, Bruneton (x_μ, x_r)
uniform sampler2D uHillaireMultiScatteringLut; // rgb: Ψ_ms per unit sun intensity; a: f_ms
uniform float uHillaireMsScale;       // 1: multiple scattering on; 0: single scattering only
uniform float uHillaireCameraHeight;  // camera altitude above the bottom sphere (m), from the CPU

const float HILLAIRE_INFINITY = 1.0e30;

float HillaireAtmosphereHeight() { return uTopRadius - uBottomRadius; }

// ρ = sqrt(r² − R²) for r = R + h (distance to the ground horizon)
float HillaireHorizonDistance(float h) {
    h = max(h, 0.0);
    return sqrt(h * (2.0 * uBottomRadius + h));
}

float HillaireTopHorizonDistance() { return HillaireHorizonDistance(HillaireAtmosphereHeight()); }

// cos of the zenith angle of the ground's tangent ray from altitude h (≤ 0).
float HillaireHorizonCosine(float h) {
    return -HillaireHorizonDistance(h) / (uBottomRadius + max(h, 0.0));
}

bool HillaireRayHitsGround(float h, float mu) { return mu < HillaireHorizonCosine(h); }

// Altitude at distance t along the ray (h, μ).
float HillaireHeightAlong(float h, float mu, float t) {
    float r = uBottomRadius + h;
    float num = t * (t + 2.0 * r * mu);
    float rt = SafeSqrt(r * r + num);
    return h + num / max(rt + r, 1.0);
}

// Distance from altitude h ≤ top to the top sphere along μ (the far intersection).
float HillaireDistanceToTop(float h, float mu) {
    float r = uBottomRadius + h;
    float a = max(HillaireAtmosphereHeight() - h, 0.0);  // r_top − r
    float rmu = r * mu;
    float num = a * (uTopRadius + r);                     // r_top² − r²
    float s = SafeSqrt(num + rmu * rmu);
    return mu > 0.0 ? num / max(rmu + s, 1.0e-6) : s - rmu;
}

// Distance to the ground along a ray that hits it (HillaireRayHitsGround).
float HillaireDistanceToGround(float h, float mu) {
    h = max(h, 0.0);
    float r = uBottomRadius + h;
    float rho2 = h * (2.0 * uBottomRadius + h);
    float rmu = r * mu;
    return rho2 / max(-rmu + SafeSqrt(rmu * rmu - rho2), 1.0e-6);
}

// The part of the ray (h, μ) inside the atmosphere, clipped at maxDist and (clipGround) at the
// ground: (t0, t1), or (−1, −1). From above the top, t0 is the entry point (Hillaire §6).
vec2 HillaireRaySegmentClipped(float h, float mu, float maxDist, bool clipGround) {
    float r = uBottomRadius + h;
    float a = HillaireAtmosphereHeight() - h;  // r_top − r, negative above the top
    float rmu = r * mu;
    float num = a * (uTopRadius + r);          // r_top² − r²
    float disc = num + rmu * rmu;
    if (disc < 0.0) return vec2(-1.0);
    float s = sqrt(disc);
    float t0, t1;
    if (a >= 0.0) {
        t0 = 0.0;
        t1 = HillaireDistanceToTop(h, mu);
    } else {
        t1 = s - rmu;
        if (t1 <= 0.0) return vec2(-1.0);
        t0 = max(-num / max(s - rmu, 1.0e-6), 0.0);  // = −rμ − s without cancellation
    }
    if (clipGround && HillaireRayHitsGround(h, mu)) t1 = min(t1, HillaireDistanceToGround(h, mu));
    t1 = min(t1, maxDist);
    if (t1 <= t0) return vec2(-1.0);
    return vec2(t0, t1);
}

vec2 HillaireRaySegment(float h, float mu, float maxDist) {
    return HillaireRaySegmentClipped(h, mu, maxDist, true);
}

// ---- LUT coordinates ---------------------------------------------------------------------------
// A unit coordinate x ∈ [0, 1] lands on texel centres 0 … n−1 (no half-texel loss at the ends).
float HillaireUnitToTexel(float x, float n) { return 0.5 / n + x * (1.0 - 1.0 / n); }

vec2 HillaireTransmittanceUv(float h, float mu) {
    h = clamp(h, 0.0, HillaireAtmosphereHeight());
    float H = HillaireTopHorizonDistance();
    float rho = HillaireHorizonDistance(h);
    float d = HillaireDistanceToTop(h, mu);
    float dMin = HillaireAtmosphereHeight() - h;
    float dMax = rho + H;
    float xMu = clamp((d - dMin) / max(dMax - dMin, 1.0e-3), 0.0, 1.0);
    float xR = clamp(rho / H, 0.0, 1.0);
    vec2 n = vec2(textureSize(uHillaireTransmittanceLut, 0));
    return vec2(HillaireUnitToTexel(xMu, n.x), HillaireUnitToTexel(xR, n.y));
}

// Inverse of the above for unit coordinates (x_μ, x_r): altitude h and zenith cosine μ.
void HillaireTransmittanceParams(vec2 unit, out float h, out float mu) {
    float H = HillaireTopHorizonDistance();
    float rho = H * unit.y;
    float R = uBottomRadius;
    float r = sqrt(rho * rho + R * R);
    h = rho * rho / (r + R);
    float a = max(HillaireAtmosphereHeight() - h, 0.0);
    float d = a + unit.x * (rho + H - a);
    mu = d <= 0.0 ? 1.0 : ClampCosine((a * (uTopRadius + r) - d * d) / (2.0 * r * d));
}

// Transmittance from altitude h to the top of the atmosphere along μ (no ground test).
vec3 HillaireTransmittanceToTop(float h, float mu) {
    return texture(uHillaireTransmittanceLut, HillaireTransmittanceUv(h, mu)).rgb;
}

// Transmittance of sunlight reaching altitude h with the sun at zenith cosine μ_s: zero in the
// planet's shadow.
vec3 HillaireSunTransmittanceAt(float h, float muS) {
    return HillaireRayHitsGround(h, muS) ? vec3(0.0) : HillaireTransmittanceToTop(h, muS);
}

// Ψ_ms(h, μ_s) per unit sun intensity (Hillaire 2020 eq. 10), uv linear in μ_s and in h.
vec3 HillaireMultipleScatteringAt(float h, float muS) {
    vec2 n = vec2(textureSize(uHillaireMultiScatteringLut, 0));
    vec2 unit = clamp(vec2(muS * 0.5 + 0.5, h / HillaireAtmosphereHeight()), 0.0, 1.0);
    return texture(uHillaireMultiScatteringLut,
                   vec2(HillaireUnitToTexel(unit.x, n.x), HillaireUnitToTexel(unit.y, n.y))).rgb;
}

// ---- the view-ray integral ---------------------------------------------------------------------
struct HillaireInScatter {
    vec3 rayleigh;      // ∫ T_view T_sun β_R ρ_R dt          (no phase, per unit sun intensity)
    vec3 mie;           // ∫ T_view T_sun β^s_M ρ_M dt        (no phase)
    vec3 multiple;      // ∫ T_view σ_s Ψ_ms dt               (isotropic, per unit sun intensity)
    vec3 transfer;      // ∫ T_view σ_s dt                    (f_ms integrand, Hillaire 2020 eq. 8)
    vec3 opticalDepth;  // ∫ σ_t dt from the start of the segment
    vec2 density;       // (∫ ρ_R dt, ∫ ρ_M dt): σ_t's integral is β^ext_R x + β^ext_M y (+ ozone's)
};

HillaireInScatter HillaireZeroInScatter() {
    return HillaireInScatter(vec3(0.0), vec3(0.0), vec3(0.0), vec3(0.0), vec3(0.0), vec2(0.0));
}

// One midpoint sample at distance t of width dt on the ray (h0, μ) with sun cosine μ_s and
// view–sun cosine ν; the view transmittance is taken at the sample's middle.
void HillaireAccumulate(inout HillaireInScatter acc, float h0, float mu, float muS, float nu,
                        float t, float dt, bool withMultiple) {
    float r0 = uBottomRadius + h0;
    float h = HillaireHeightAlong(h0, mu, t);
    vec2 density = DensityRM(h);
    vec3 scatR = uBetaRayleigh * density.x;
    vec3 scatM = uBetaMieScatter * density.y;
    vec3 stepDepth = (uBetaRayleigh * density.x + uBetaMieExt * density.y
                      + uOzoneAbsorption * DensityOzone(h)) * dt;
    vec3 viewT = exp(-(acc.opticalDepth + 0.5 * stepDepth));
    float muSAt = ClampCosine((r0 * muS + t * nu) / (uBottomRadius + max(h, 0.0)));
    vec3 sunT = HillaireSunTransmittanceAt(h, muSAt);
    acc.rayleigh += viewT * sunT * scatR * dt;
    acc.mie += viewT * sunT * scatM * dt;
    acc.transfer += viewT * (scatR + scatM) * dt;
    if (withMultiple) acc.multiple += viewT * (scatR + scatM) * HillaireMultipleScatteringAt(h, muSAt) * dt;
    acc.opticalDepth += stepDepth;
    acc.density += density * dt;
}

// n samples on [a, b], t = a + L s² (denseAtStart) or t = b − L s², in increasing t.
void HillaireMarchPiece(inout HillaireInScatter acc, float h0, float mu, float muS, float nu,
                        float a, float b, bool denseAtStart, int n, bool withMultiple) {
    float L = b - a;
    if (L <= 0.0 || n <= 0) return;
    float fn = float(n);
    for (int k = 0; k < n; ++k) {
        float s = denseAtStart ? (float(k) + 0.5) / fn : (fn - float(k) - 0.5) / fn;
        float t = denseAtStart ? a + L * s * s : b - L * s * s;
        HillaireAccumulate(acc, h0, mu, muS, nu, t, 2.0 * L * s / fn, withMultiple);
    }
}

// The integral over [t0, t1] of the ray (h0, μ), `steps` samples dense toward low altitudes.
// `multiple` is scaled by uHillaireMsScale when withMultiple is set.
HillaireInScatter HillaireIntegrateSegment(float h0, float mu, float muS, float nu, float t0, float t1,
                                           int steps, bool withMultiple) {
    HillaireInScatter acc = HillaireZeroInScatter();
    if (t1 <= t0) return acc;
    steps = max(steps, 2);
    float tp = -(uBottomRadius + h0) * mu;  // perigee: lowest altitude of the line
    if (tp <= t0) {
        HillaireMarchPiece(acc, h0, mu, muS, nu, t0, t1, true, steps, withMultiple);
    } else if (tp >= t1) {
        HillaireMarchPiece(acc, h0, mu, muS, nu, t0, t1, false, steps, withMultiple);
    } else {
        int n1 = steps / 2;  // half each side: both pieces are densest at the perigee
        HillaireMarchPiece(acc, h0, mu, muS, nu, t0, tp, false, n1, withMultiple);
        HillaireMarchPiece(acc, h0, mu, muS, nu, tp, t1, true, steps - n1, withMultiple);
    }
    acc.multiple *= uHillaireMsScale;
    return acc;
}

// Radiance of an integrated segment seen along a ray with view–sun cosine ν.
vec3 HillaireRadiance(HillaireInScatter acc, float nu) {
    return uSunIntensity * (PhaseRayleigh(nu) * acc.rayleigh
                            + PhaseMieCornetteShanks(nu, uMieG) * acc.mie + acc.multiple);
}

float HillaireMean(vec3 v) { return dot(v, vec3(1.0 / 3.0)); }
