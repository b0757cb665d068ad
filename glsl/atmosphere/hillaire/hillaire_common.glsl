// Method 4, beyond the thesis: the shared part of Hillaire's LUT atmosphere (S. Hillaire, "A
// Scalable and Production Ready Sky and Atmosphere Rendering Technique", EGSR 2020). The model
// and constants are the thesis's (spec/002 §1, §7; glsl/atmosphere/model.glsl): Rayleigh + Mie,
// exponential densities, β^ext_M = 1.1 β^scatt_M, Cornette–Shanks phase, plus model.glsl's
// optional ozone (absorption only). This file holds the (h, μ) ray geometry, the transmittance
// and multiple-scattering LUT lookups, and the view-ray integrator that every Hillaire pass and
// hillaire_lookup.glsl share. Radiance is uSunIntensity × these integrals, as in model.glsl.
// Failure cases guarded: μ outside [−1, 1] (ClampCosine), square roots of rounding negatives
// (SafeSqrt), r² − R² cancelling in float32 at planet scale (never formed), rays starting above
// the top (moved to the entry point), rays missing the atmosphere (empty segment), the sun below
// the local horizon (planet shadow: 0), h < 0 (clamped), zero-length segments.
#include "../model.glsl"

uniform sampler2D uHillaireTransmittanceLut;   // rgb: transmittance to the top, Bruneton (x_μ, x_r)
uniform sampler2D uHillaireMultiScatteringLut; // rgb: Ψ_ms per unit sun intensity; a: f_ms
uniform float uHillaireMsScale;       // 1: multiple scattering on; 0: single scattering only
uniform float uHillaireCameraHeight;  // camera altitude above the bottom sphere (m), from the CPU

const float HILLAIRE_INFINITY = 1.0e30;     // m: "no limit" for a segment's far end
const float HILLAIRE_MIN_RADIUS_SUM = 1.0;  // m: floor of r(t) + r, a sum of two radii (≥ 2 R)
const float HILLAIRE_MIN_DENOM = 1.0e-6;    // m: floor of a distance formula's denominator
const float HILLAIRE_MIN_SPAN = 1.0e-3;     // m: floor of d_max − d_min (zero at the top)

// Height of the atmosphere, r_top − R, in metres.
float HillaireAtmosphereHeight() { return uTopRadius - uBottomRadius; }

// ρ = sqrt(r² − R²) for r = R + h: the distance in metres to the ground's horizon from altitude
// h (m), written as sqrt(h (2R + h)) so nothing cancels in float32 (R ≈ 6.4·10⁶ m: r² ≈ 4·10¹³
// has an ulp of 4·10⁶ m²). h < 0 is clamped to 0.
float HillaireHorizonDistance(float h) {
    h = max(h, 0.0);
    return sqrt(h * (2.0 * uBottomRadius + h));
}

// H_top = sqrt(r_top² − R²), metres: the horizon distance from the top of the atmosphere.
float HillaireTopHorizonDistance() { return HillaireHorizonDistance(HillaireAtmosphereHeight()); }

// Zenith cosine (≤ 0) of the ray tangent to the ground from altitude h (m); h < 0 is clamped.
float HillaireHorizonCosine(float h) {
    return -HillaireHorizonDistance(h) / (uBottomRadius + max(h, 0.0));
}

// Whether the ray from altitude h (m) with zenith cosine μ meets the ground.
bool HillaireRayHitsGround(float h, float mu) { return mu < HillaireHorizonCosine(h); }

// Altitude (m) at distance t (m) along the ray (h, μ): h(t) = h + (t² + 2 r μ t)/(r(t) + r) with
// r(t) = sqrt(r² + 2 r μ t + t²), the cancellation-free form of r(t) − R. Rounding negatives
// under the root are clamped (SafeSqrt) and the denominator floored.
float HillaireHeightAlong(float h, float mu, float t) {
    float r = uBottomRadius + h;
    float num = t * (t + 2.0 * r * mu);
    float rt = SafeSqrt(r * r + num);
    return h + num / max(rt + r, HILLAIRE_MIN_RADIUS_SUM);
}

// Distance (m) from altitude h ≤ top to the far intersection with the top sphere along μ. For
// μ > 0 it uses (r_top² − r²)/(rμ + s), which does not cancel; h above the top gives a = 0.
float HillaireDistanceToTop(float h, float mu) {
    float r = uBottomRadius + h;
    float a = max(HillaireAtmosphereHeight() - h, 0.0);  // r_top − r
    float rmu = r * mu;
    float num = a * (uTopRadius + r);                     // r_top² − r²
    float s = SafeSqrt(num + rmu * rmu);
    return mu > 0.0 ? num / max(rmu + s, HILLAIRE_MIN_DENOM) : s - rmu;
}

// Distance (m) to the ground along a ray that hits it (HillaireRayHitsGround):
// d_ground = ρ² / (−rμ + sqrt(r²μ² − ρ²)), free of cancellation; h < 0 is clamped.
float HillaireDistanceToGround(float h, float mu) {
    h = max(h, 0.0);
    float r = uBottomRadius + h;
    float rho2 = h * (2.0 * uBottomRadius + h);
    float rmu = r * mu;
    return rho2 / max(-rmu + SafeSqrt(rmu * rmu - rho2), HILLAIRE_MIN_DENOM);
}

// The part of the ray (h, μ) inside the atmosphere, clipped at maxDist (m) and, with clipGround,
// at the ground: (t0, t1) in metres, or (−1, −1) when empty (the ray misses the top sphere,
// points away from it, or the clip leaves nothing). From above the top, t0 is the entry point
// (Hillaire 2020 §6, space views).
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
        t0 = max(-num / max(s - rmu, HILLAIRE_MIN_DENOM), 0.0);  // = −rμ − s, no cancellation
    }
    if (clipGround && HillaireRayHitsGround(h, mu)) t1 = min(t1, HillaireDistanceToGround(h, mu));
    t1 = min(t1, maxDist);
    if (t1 <= t0) return vec2(-1.0);
    return vec2(t0, t1);
}

// HillaireRaySegmentClipped, clipped at the ground.
vec2 HillaireRaySegment(float h, float mu, float maxDist) {
    return HillaireRaySegmentClipped(h, mu, maxDist, true);
}

// ---- LUT coordinates ---------------------------------------------------------------------------
// A unit coordinate x ∈ [0, 1] mapped onto the texel centres 0 … n−1 of a texture n texels wide
// (no half-texel lost at the ends).
float HillaireUnitToTexel(float x, float n) { return 0.5 / n + x * (1.0 - 1.0 / n); }

// Texture coordinates of the transmittance LUT for altitude h (m) and zenith cosine μ, in the
// parametrisation Hillaire 2020 §4 takes from Bruneton & Neyret 2008 and Bruneton 2017:
// x_r = ρ/H_top, x_μ = (d − d_min)/(d_max − d_min) with d = d_top(h, μ), d_min = r_top − r and
// d_max = ρ + H_top. It covers every ray that misses the ground. h is clamped into the
// atmosphere, both coordinates into [0, 1], and d_max − d_min (0 at the top) floored.
vec2 HillaireTransmittanceUv(float h, float mu) {
    h = clamp(h, 0.0, HillaireAtmosphereHeight());
    float H = HillaireTopHorizonDistance();
    float rho = HillaireHorizonDistance(h);
    float d = HillaireDistanceToTop(h, mu);
    float dMin = HillaireAtmosphereHeight() - h;
    float dMax = rho + H;
    float xMu = clamp((d - dMin) / max(dMax - dMin, HILLAIRE_MIN_SPAN), 0.0, 1.0);
    float xR = clamp(rho / H, 0.0, 1.0);
    vec2 n = vec2(textureSize(uHillaireTransmittanceLut, 0));
    return vec2(HillaireUnitToTexel(xMu, n.x), HillaireUnitToTexel(xR, n.y));
}

// Inverse of HillaireTransmittanceUv for unit coordinates (x_μ, x_r): altitude h (m) and zenith
// cosine μ. d ≤ 0 (at the top, looking up) gives μ = 1; μ is clamped into [−1, 1].
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

// Transmittance (rgb, [0, 1]) from altitude h (m) to the top of the atmosphere along μ. No
// ground test: a ray that hits the ground reads the LUT as if it did not.
vec3 HillaireTransmittanceToTop(float h, float mu) {
    return texture(uHillaireTransmittanceLut, HillaireTransmittanceUv(h, mu)).rgb;
}

// Transmittance (rgb, [0, 1]) of sunlight reaching altitude h (m) with the sun at zenith cosine
// μ_s: the LUT times "the sun is above the local horizon" (Hillaire 2020 eq. 1's T_sun), so 0
// in the planet's shadow.
vec3 HillaireSunTransmittanceAt(float h, float muS) {
    return HillaireRayHitsGround(h, muS) ? vec3(0.0) : HillaireTransmittanceToTop(h, muS);
}

// Ψ_ms(h, μ_s), the multiple-scattering transfer per unit sun intensity (Hillaire 2020 eq. 10;
// the LUT is built in multiscattering_lut.frag), read with uv linear in μ_s and in h (m).
// Coordinates outside the LUT are clamped to its edges.
vec3 HillaireMultipleScatteringAt(float h, float muS) {
    vec2 n = vec2(textureSize(uHillaireMultiScatteringLut, 0));
    vec2 unit = clamp(vec2(muS * 0.5 + 0.5, h / HillaireAtmosphereHeight()), 0.0, 1.0);
    return texture(uHillaireMultiScatteringLut,
                   vec2(HillaireUnitToTexel(unit.x, n.x), HillaireUnitToTexel(unit.y, n.y))).rgb;
}

// ---- the view-ray integral ---------------------------------------------------------------------
// The integrals of one segment, per unit sun intensity. Rayleigh and Mie are kept without their
// phase functions: ν is constant along a ray, so the lookup applies the phase exactly per pixel
// and the sharp Mie halo (G = 0.76) never goes through a LUT's bilinear filter.
struct HillaireInScatter {
    vec3 rayleigh;      // ∫ T_view T_sun β_R ρ_R dt          (no phase, per unit sun intensity)
    vec3 mie;           // ∫ T_view T_sun β^s_M ρ_M dt        (no phase)
    vec3 multiple;      // ∫ T_view σ_s Ψ_ms dt               (isotropic, per unit sun intensity)
    vec3 transfer;      // ∫ T_view σ_s dt                    (f_ms integrand, Hillaire 2020 eq. 8)
    vec3 opticalDepth;  // ∫ σ_t dt from the start of the segment
    vec2 density;       // (∫ ρ_R dt, ∫ ρ_M dt): σ_t's integral is β^ext_R x + β^ext_M y (+ ozone)
};

// All integrals zero (an empty segment).
HillaireInScatter HillaireZeroInScatter() {
    return HillaireInScatter(vec3(0.0), vec3(0.0), vec3(0.0), vec3(0.0), vec3(0.0), vec2(0.0));
}

// One midpoint sample of Hillaire 2020 eq. 1 (with S = single + multiple, Hillaire 2020 eq. 11)
// at distance t of width dt (m) on the ray (h0 in m, μ) with sun cosine μ_s and view–sun cosine ν.
// The sun's cosine at the sample is μ_s(t) = (r μ_s + t ν)/r(t); the view transmittance is taken
// at the sample's middle; the ozone term adds absorption only. With V ≡ 1 and no multiple
// scattering this is the thesis's method-1 integrand (spec/002 §1.5).
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
    if (withMultiple) {
        acc.multiple += viewT * (scatR + scatM) * HillaireMultipleScatteringAt(h, muSAt) * dt;
    }
    acc.opticalDepth += stepDepth;
    acc.density += density * dt;
}

// n midpoint samples on [a, b] (m), in increasing t, at t = a + L s² (denseAtStart) or
// t = b − L s² with s ∈ (0, 1): dense at the low-altitude end of a monotone-altitude piece.
// An empty piece (L ≤ 0 or n ≤ 0) adds nothing.
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

// The integrals over [t0, t1] (m) of the ray (h0, μ), with `steps` samples (at least 2). The ray
// is split at its perigee t_p = −rμ, half the samples on each side, each half densest there.
// In numpy (30 steps, 120 rays from the ground to 600 km) this errs at most 0.8 % of the peak
// channel where uniform steps err 9 % (vertical Mie at the ground); rays grazing the ground
// from altitude reach 2.5 % (splitting by length instead of in halves: 30 %). `multiple` is
// scaled by uHillaireMsScale when withMultiple is set. An empty segment gives zeros.
HillaireInScatter HillaireIntegrateSegment(float h0, float mu, float muS, float nu, float t0,
                                           float t1, int steps, bool withMultiple) {
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

// Linear radiance of an integrated segment seen with view–sun cosine ν: E_sun (uSunIntensity,
// the thesis's sun "illuminance": phases are per steradian) times the phased integrals. The
// Cornette–Shanks phase clamps G → ±1.
vec3 HillaireRadiance(HillaireInScatter acc, float nu) {
    return uSunIntensity * (PhaseRayleigh(nu) * acc.rayleigh
                            + PhaseMieCornetteShanks(nu, uMieG) * acc.mie + acc.multiple);
}

// Mean of the three channels (a transmittance's alpha summary).
float HillaireMean(vec3 v) { return dot(v, vec3(1.0 / 3.0)); }
