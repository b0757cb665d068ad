// Cloud model A: the density field and the lighting terms of the volumetric-clouds thesis
// (spec/001 §1.2–§1.4 and §1.7, after Häggström 2018 / Schneider 2015), as pure functions of
// their inputs, so that a probe shader (glsl/tests/clouds_probe.frag) compares each one with its
// numpy twin (app/sim/clouds.py). cloud_march.frag marches them.
// Conventions: y is up (the thesis writes p.z); lengths in metres; every texture value, weather
// map w = (mc_n0, mc_n1, mc_a, mc_d), shape (f_r, f_g, f_b, f_a) and detail (d_r, d_g, d_b),
// in [0, 1]. Each function states its equation, units and failure case; the thesis's errata
// (spec/001 §1.10) are resolved at the functions they concern, and the printed algorithms'
// missing sums (item 3) in cloud_march.frag. Failure cases guarded: the divisions by zero of
// spec/001 eq. 4.7 and spec/001 eq. 4.13 and of a zero-thickness layer; Remap alone has no guard.

#include "math.glsl"
#include "phase.glsl"
#include "intersect.glsl"

// The thesis's constants (spec/001 §1.3–§1.4).
const float CLOUD_MIN_THICKNESS = 1e-3;         // m, floor of al_m − al_b (HeightFraction)
const float CLOUD_ROUND_BOTTOM_END = 0.07;      // height fraction where the base is round
const float CLOUD_ROUND_TOP_START = 0.2;        // fraction of mc_a where the top starts to round
const float CLOUD_DENSITY_BOTTOM_END = 0.15;    // height fraction where density stops growing
const float CLOUD_DENSITY_TOP_START = 0.9;      // height fraction where density starts to fade
const float CLOUD_DENSITY_SCALE = 2.0;          // HeightDensity's factor 2
const float CLOUD_FBM_W1 = 0.625;               // octave weights of the Worley fBm sums
const float CLOUD_FBM_W2 = 0.25;
const float CLOUD_FBM_W3 = 0.125;
const float CLOUD_DETAIL_MAX = 0.35;            // the detail's erosion at most (n_g = 0)
const float CLOUD_DETAIL_COVERAGE_FALLOFF = 0.75;  // per unit coverage, in the exponent
const float CLOUD_DETAIL_INVERT_RATE = 5.0;     // 1/height fraction: DB fully inverted at pa 0.2

// spec/001 eq. 4.1: v from [ia, fa] onto [in, fn], unclamped. (saturate, spec/001 eq. 4.2,
// is glsl/common/math.glsl's; lerp, spec/001 eq. 4.3, is GLSL's mix.) Failure case: ia = fa
// divides by 0; there is no guard here (the equation exactly), so callers pass ia ≠ fa, as the
// guarded wrappers below do.
float Remap(float v, float ia, float fa, float in_, float fn) {
    return in_ + (v - ia) * (fn - in_) / (fa - ia);
}

// spec/001 eq. 4.4: pa, the height fraction in [0, 1] of a height in metres above the reference
// (box: y; sphere: radius − planet radius) in the layer [al_b, al_m]. Failure case: al_m ≤ al_b
// divides by max(al_m − al_b, 1 mm); the Python side refuses a layer thinner than 1 m first.
float HeightFraction(float height, float baseHeight, float maxHeight) {
    return saturate((height - baseHeight) / max(maxHeight - baseHeight, CLOUD_MIN_THICKNESS));
}

// spec/001 eq. 4.5: Nubosidad = lerp(mc_n0, mc_n1, n_g), the weather map's coverage in [0, 1]
// at the global coverage n_g.
float Nubosidad(vec2 lowHighCoverage, float coverage) {
    return mix(lowHighCoverage.x, lowHighCoverage.y, coverage);
}

// spec/001 eq. 4.6: RoundBottom = sat(Remap(pa, 0, 0.07, 0, 1)), in [0, 1].
float RoundBottom(float pa) {
    return saturate(Remap(pa, 0.0, CLOUD_ROUND_BOTTOM_END, 0.0, 1.0));
}

// spec/001 eq. 4.7: RoundTop = sat(Remap(pa, 0.2 mc_a, mc_a, 1, 0)), in [0, 1]. Failure case
// (erratum §1.10): at mc_a = 0 it is Remap(pa, 0, 0, 1, 0), a division by 0; it returns 0 there
// (a cloud of zero maximum height is no cloud).
float RoundTop(float pa, float mca) {
    return mca > 0.0 ? saturate(Remap(pa, CLOUD_ROUND_TOP_START * mca, mca, 1.0, 0.0)) : 0.0;
}

// spec/001 eq. 4.8: Altura = RoundBottom · RoundTop, in [0, 1].
float HeightShape(float pa, float mca) { return RoundBottom(pa) * RoundTop(pa, mca); }

// spec/001 eq. 4.9: DensityBottom = pa · sat(Remap(pa, 0, 0.15, 0, 1)), in [0, 1].
float DensityBottom(float pa) {
    return pa * saturate(Remap(pa, 0.0, CLOUD_DENSITY_BOTTOM_END, 0.0, 1.0));
}
// spec/001 eq. 4.10: DensityTop = sat(Remap(pa, 0.9, 1, 1, 0)), in [0, 1].
float DensityTop(float pa) {
    return saturate(Remap(pa, CLOUD_DENSITY_TOP_START, 1.0, 1.0, 0.0));
}

// spec/001 eq. 4.11: Densidad = d_g · DensityBottom · DensityTop · mc_d · 2, ≥ 0 (d_g ≤ 10).
float HeightDensity(float pa, float globalDensity, float mcd) {
    return globalDensity * DensityBottom(pa) * DensityTop(pa) * mcd * CLOUD_DENSITY_SCALE;
}

// spec/001 eq. 4.12: FormaBase = Remap(f_r, (0.625 f_g + 0.25 f_b + 0.125 f_a) − 1, 1, 0, 1),
// the Perlin–Worley base shape eroded by the Worley fBm, in [0, 1] for inputs in [0, 1]. The
// weights sum to 1, so ia ≤ 0 < 1 = fa: no division by 0.
float ShapeBase(vec4 shape) {
    float worleyFbm = shape.g * CLOUD_FBM_W1 + shape.b * CLOUD_FBM_W2 + shape.a * CLOUD_FBM_W3;
    return Remap(shape.r, worleyFbm - 1.0, 1.0, 0.0, 1.0);
}

// spec/001 eq. 4.13: Forma = sat(Remap(FormaBase · Altura, 1 − n_g · Nubosidad, 1, 0, 1)), in
// [0, 1]. Failure case (erratum §1.10 item 10): at n_g · Nubosidad = 0 it is Remap(x, 1, 1, 0,
// 1), a division by 0; it returns 0 there (no coverage, no cloud), which is also the formula's
// limit for every x < 1.
float CoverageShape(float baseTimesHeight, float coverage, float nubosidad) {
    float c = coverage * nubosidad;
    return c > 0.0 ? saturate(Remap(baseTimesHeight, 1.0 - c, 1.0, 0.0, 1.0)) : 0.0;
}

// spec/001 eq. 4.14: DetalleBase DB = 0.625 d_r + 0.25 d_g + 0.125 d_b, and spec/001 eq. 4.15:
// Detalle = 0.35 e^(−0.75 n_g) · lerp(DB, 1 − DB, sat(5 pa)), in [0, 0.35]. Erratum (§1.10
// item 5): the printed exponent e^(+0.75 n_g) contradicts "at most 0.35"; the sign is the one of
// Häggström's code, so that erosion can only remove density (criterion C7): Remap(F, D, 1, 0, 1)
// = (F − D)/(1 − D) ≤ F for F ≤ 1.
float DetailErosion(vec3 detail, float pa, float coverage) {
    float db = detail.r * CLOUD_FBM_W1 + detail.g * CLOUD_FBM_W2 + detail.b * CLOUD_FBM_W3;
    return CLOUD_DETAIL_MAX * exp(-coverage * CLOUD_DETAIL_COVERAGE_FALLOFF)
         * mix(db, 1.0 - db, saturate(pa * CLOUD_DETAIL_INVERT_RATE));
}

// spec/001 eq. 4.16: DensidadTotal = sat(Remap(Forma, Detalle, 1, 0, 1)) · Densidad, the full
// density, dimensionless, ≥ 0; withDetail false gives the shape-only density Forma · Densidad
// (the thesis's "density without detail", Algorithm 2), never below the full one. weather =
// (mc_n0, mc_n1, mc_a, mc_d). Detalle ≤ 0.35 < 1, so the Remap never divides by 0.
float CloudDensityFromSamples(vec4 weather, vec4 shape, vec3 detail, float pa, float coverage,
                              float globalDensity, bool withDetail) {
    float dns = HeightDensity(pa, globalDensity, weather.a);
    float forma = CoverageShape(ShapeBase(shape) * HeightShape(pa, weather.b), coverage,
                                Nubosidad(weather.rg, coverage));
    if (!withDetail || forma <= 0.0) return forma * dns;
    float det = DetailErosion(detail, pa, coverage);
    return saturate(Remap(forma, det, 1.0, 0.0, 1.0)) * dns;
}

// ---- lighting (spec/001 §1.7) --------------------------------------------------------------

// spec/001 eq. 4.18: Beer's law, A(b, d_s) = e^(−b d_s), a transmittance in (0, 1] for an
// absorption b ≥ 0 and an accumulated density d_s ≥ 0.
float Beer(float absorption, float ds) { return exp(-absorption * ds); }

// spec/001 eq. 4.20: the silver lobe IS(cos θ) = cs_i · sat(cos θ)^cs_e, ≥ 0 (1/sr, as the
// phase it competes with). Erratum (§1.10 item 6): the thesis applies Sat to θ; Sat(cos θ) is
// what the criteria's IOS values assume. Failure case: pow(0, e) is undefined for e ≤ 0 in
// GLSL, so cos θ ≤ 0 returns 0 without calling it.
float SilverLobe(float cosTheta, float intensity, float exponent) {
    float c = saturate(cosTheta);
    return c > 0.0 ? intensity * pow(c, exponent) : 0.0;
}

// spec/001 eq. 4.21: IOS(cos θ) = lerp(max(p(cos θ, in_s), IS(cos θ)), p(cos θ, −out_s), ivo),
// in 1/sr, with p the Henyey–Greenstein phase of spec/001 eq. 4.19 (HenyeyGreenstein in
// glsl/common/phase.glsl). Failure case: HG at |g| → 1 is a delta; it is finite for |g| < 1,
// the parameters keep g in [−1, 1], and at |g| = 1, cos θ = ±1, the denominator
// 1 + g² − 2g cos θ ≥ (1 − |g|)² is floored at 1e-6.
float InOutScatter(float cosTheta, float inScatter, float outScatter, float inVsOut,
                   float silverIntensity, float silverExponent) {
    float forward = max(HenyeyGreenstein(cosTheta, inScatter),
                        SilverLobe(cosTheta, silverIntensity, silverExponent));
    return mix(forward, HenyeyGreenstein(cosTheta, -outScatter), inVsOut);
}

// spec/001 eq. 4.22: the powder term L(b, d_s) = 2 A(b, d_s) (1 − A(b, 2 d_s)), in [0, 0.5]:
// dark edges where little density lies toward the light. (The energy of spec/001 eq. 4.23,
// E = L · IOS, is cloud_march.frag's LightEnergy.)
float Powder(float absorption, float ds) {
    return 2.0 * Beer(absorption, ds) * (1.0 - Beer(absorption, 2.0 * ds));
}
