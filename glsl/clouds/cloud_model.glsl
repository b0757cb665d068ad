// Cloud model A: the density field and the lighting terms of the volumetric-clouds thesis
// (spec/001, after Häggström 2018 / Schneider 2015), as pure functions of their inputs so a
// probe shader (glsl/tests/clouds_probe.frag) can compare each one with its numpy twin
// (app/sim/clouds.py).
//
// Conventions: y is up (the thesis writes p.z); lengths in metres; every texture value in [0, 1].
//
// Helpers (spec/001 §1.2)
//   Remap(v, ia, fa, in, fn) = in + (v − ia)(fn − in)/(fa − ia)             spec/001 eq. 4.1
//   saturate(v) = clamp(v, 0, 1) (glsl/common/math.glsl)                    spec/001 eq. 4.2
//   lerp = GLSL mix                                                         spec/001 eq. 4.3
//   pa = HeightFraction = sat((h − al_b)/(al_m − al_b))                     spec/001 eq. 4.4
// Coverage and density (§1.3–1.4), weather map w = (mc_n0, mc_n1, mc_a, mc_d):
//   Nubosidad      = lerp(mc_n0, mc_n1, n_g)                                spec/001 eq. 4.5
//   RoundBottom    = sat(Remap(pa, 0, 0.07, 0, 1))                          spec/001 eq. 4.6
//   RoundTop       = sat(Remap(pa, 0.2 mc_a, mc_a, 1, 0))                   spec/001 eq. 4.7
//   Altura         = RoundBottom · RoundTop                                 spec/001 eq. 4.8
//   DensityBottom  = pa · sat(Remap(pa, 0, 0.15, 0, 1))                     spec/001 eq. 4.9
//   DensityTop     = sat(Remap(pa, 0.9, 1.0, 1, 0))                         spec/001 eq. 4.10
//   Densidad       = d_g · DensityBottom · DensityTop · mc_d · 2            spec/001 eq. 4.11
//   FormaBase      = Remap(f_r, (0.625 f_g + 0.25 f_b + 0.125 f_a) − 1, 1, 0, 1)
//                                                                           spec/001 eq. 4.12
//   Forma          = sat(Remap(FormaBase · Altura, 1 − n_g·Nubosidad, 1, 0, 1))
//                                                                           spec/001 eq. 4.13
//   DetalleBase    = 0.625 d_r + 0.25 d_g + 0.125 d_b                       spec/001 eq. 4.14
//   Detalle        = 0.35 e^(−0.75 n_g) · lerp(DB, 1 − DB, sat(5 pa))       spec/001 eq. 4.15
//   DensidadTotal  = sat(Remap(Forma, Detalle, 1, 0, 1)) · Densidad         spec/001 eq. 4.16
// Lighting (§1.7):
//   Beer           A(b, d_s) = e^(−b d_s)                                   spec/001 eq. 4.18
//   Henyey–Greenstein p(cos θ, g) = (1 − g²) / (4π (1 + g² − 2g cos θ)^1.5)
//                                                                           spec/001 eq. 4.19
//   Silver lobe    IS(cos θ) = cs_i · sat(cos θ)^cs_e                       spec/001 eq. 4.20
//   IOS(cos θ)     = lerp(max(p(cos θ, in_s), IS(cos θ)), p(cos θ, −out_s), ivo)
//                                                                           spec/001 eq. 4.21
//   Powder         L(b, d_s) = 2 A(b, d_s) (1 − A(b, 2 d_s))                spec/001 eq. 4.22
//   Energy         E = L(b, d_s) · IOS(cos θ)                               spec/001 eq. 4.23
//
// Errata resolved (spec/001 §1.10)
// * spec/001 eq. 4.15: the printed exponent e^(+0.75 n_g) contradicts "at most 0.35"; we use
//   e^(−0.75 n_g) as Häggström's code does (§1.10 item 5), so Detalle ∈ [0, 0.35] and erosion
//   can only remove density (criterion C7): Remap(F, D, 1, 0, 1) = (F − D)/(1 − D) ≤ F for F ≤ 1.
// * spec/001 eq. 4.13 at n_g = 0 (or Nubosidad = 0) is Remap(x, 1, 1, 0, 1), a division by
//   zero (§1.10 item 10): CoverageShape returns 0 there (no coverage, no cloud), which is also
//   the limit of the formula for every x < 1.
// * spec/001 eq. 4.7 with mc_a = 0 is Remap(pa, 0, 0, 1, 0), the same division: RoundTop
//   returns 0 (a cloud of zero maximum height is no cloud).
// * spec/001 eq. 4.20 applies Sat to θ: we use Sat(cos θ) (item 6), which the criteria's IOS
//   values assume.
// * The printed algorithms never accumulate the densities (item 3): the view and light
//   marches in cloud_march.frag sum them.
//
// Failure cases
// * al_m ≤ al_b: HeightFraction divides by max(al_m − al_b, 1 mm); the Python side rejects a
//   layer thinner than 1 m before that.
// * Remap itself has no guard (it is spec/001 eq. 4.1 exactly): call it only with ia ≠ fa, as
//   the guarded wrappers here do.
// * HG with |g| → 1 is a delta: finite for |g| < 1; g is limited to [−1, 1] by the parameters
//   and 1 + g² − 2g cos θ ≥ (1 − |g|)² stays positive except at |g| = 1, cos θ = ±1, guarded
//   by a 1e-6 floor.

#include "math.glsl"
#include "phase.glsl"
#include "intersect.glsl"

// spec/001 eq. 4.1
float Remap(float v, float ia, float fa, float in_, float fn) {
    return in_ + (v - ia) * (fn - in_) / (fa - ia);
}

// spec/001 eq. 4.4: height fraction from a height above the reference (box: y; sphere:
// radius − planet radius).
float HeightFraction(float height, float baseHeight, float maxHeight) {
    return saturate((height - baseHeight) / max(maxHeight - baseHeight, 1e-3));
}

// spec/001 eq. 4.5
float Nubosidad(vec2 lowHighCoverage, float coverage) {
    return mix(lowHighCoverage.x, lowHighCoverage.y, coverage);
}

// spec/001 eq. 4.6
float RoundBottom(float pa) { return saturate(Remap(pa, 0.0, 0.07, 0.0, 1.0)); }

// spec/001 eq. 4.7, guarded at mc_a = 0 (see errata above)
float RoundTop(float pa, float mca) {
    return mca > 0.0 ? saturate(Remap(pa, 0.2 * mca, mca, 1.0, 0.0)) : 0.0;
}

// spec/001 eq. 4.8
float HeightShape(float pa, float mca) { return RoundBottom(pa) * RoundTop(pa, mca); }

// spec/001 eq. 4.9
float DensityBottom(float pa) { return pa * saturate(Remap(pa, 0.0, 0.15, 0.0, 1.0)); }
// spec/001 eq. 4.10
float DensityTop(float pa) { return saturate(Remap(pa, 0.9, 1.0, 1.0, 0.0)); }

// spec/001 eq. 4.11
float HeightDensity(float pa, float globalDensity, float mcd) {
    return globalDensity * DensityBottom(pa) * DensityTop(pa) * mcd * 2.0;
}

// spec/001 eq. 4.12
float ShapeBase(vec4 shape) {
    float worleyFbm = shape.g * 0.625 + shape.b * 0.25 + shape.a * 0.125;
    return Remap(shape.r, worleyFbm - 1.0, 1.0, 0.0, 1.0);
}

// spec/001 eq. 4.13, with the n_g · Nubosidad = 0 guard
float CoverageShape(float baseTimesHeight, float coverage, float nubosidad) {
    float c = coverage * nubosidad;
    return c > 0.0 ? saturate(Remap(baseTimesHeight, 1.0 - c, 1.0, 0.0, 1.0)) : 0.0;
}

// spec/001 eq. 4.14 (DetalleBase) and spec/001 eq. 4.15 (Detalle, the exponent sign fixed)
float DetailErosion(vec3 detail, float pa, float coverage) {
    float db = detail.r * 0.625 + detail.g * 0.25 + detail.b * 0.125;
    return 0.35 * exp(-coverage * 0.75) * mix(db, 1.0 - db, saturate(pa * 5.0));
}

// spec/001 eq. 4.16: the full density; withDetail false is the shape-only density, Forma ·
// Densidad (the thesis's "density without detail", Algorithm 2). weather = (mc_n0, mc_n1, mc_a,
// mc_d).
float CloudDensityFromSamples(vec4 weather, vec4 shape, vec3 detail, float pa, float coverage,
                              float globalDensity, bool withDetail) {
    float dns = HeightDensity(pa, globalDensity, weather.a);
    float forma = CoverageShape(ShapeBase(shape) * HeightShape(pa, weather.b), coverage,
                                Nubosidad(weather.rg, coverage));
    if (!withDetail || forma <= 0.0) return forma * dns;
    float det = DetailErosion(detail, pa, coverage);
    return saturate(Remap(forma, det, 1.0, 0.0, 1.0)) * dns;
}

// ---- lighting ------------------------------------------------------------------------------

// spec/001 eq. 4.18: Beer's law
float Beer(float absorption, float ds) { return exp(-absorption * ds); }

// spec/001 eq. 4.20, with Sat(cos θ) (erratum 6)
float SilverLobe(float cosTheta, float intensity, float exponent) {
    float c = saturate(cosTheta);
    return c > 0.0 ? intensity * pow(c, exponent) : 0.0;
}

// spec/001 eq. 4.21
float InOutScatter(float cosTheta, float inScatter, float outScatter, float inVsOut,
                   float silverIntensity, float silverExponent) {
    float forward = max(HenyeyGreenstein(cosTheta, inScatter),
                        SilverLobe(cosTheta, silverIntensity, silverExponent));
    return mix(forward, HenyeyGreenstein(cosTheta, -outScatter), inVsOut);
}

// spec/001 eq. 4.22
float Powder(float absorption, float ds) {
    return 2.0 * Beer(absorption, ds) * (1.0 - Beer(absorption, 2.0 * ds));
}
