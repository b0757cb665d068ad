// =============================================================================================
// The rim silhouettes of spec/003 §2.13 as functions a surface shader (or the screen-space
// composite, edges.frag) calls: each returns an outline weight in [0, 1] — the amount of outline
// colour mixed over the shaded colour (the thesis multiplies, i.e. darkens, with the rim instead
// of adding it; mixing toward a black outline colour is that product).
//
// The rim coordinate: x = saturate(1 − (n·v)/r), r = the n·v below which the outline band lies
// (shading.contour_rim): 0 for n·v ≥ r, 1 at the silhouette (n·v = 0). The thesis's rim value
// 1 − n·v thresholded at 1 − r is the same band.
//   RimOutlineThreshold(nv, r)  variation 1: ThresholdStep(x, 0), binary (1 where n·v < r)
//   RimOutlineSoftStair(nv, r)  variation 2: the soft staircase of x·(1 + step), step
//                               RIM_STAIR_STEP = 1/3, step_soft = step / 2 (spec/003 eq. 8.2,
//                               spec/003 eq. 8.3 and spec/003 eq. 8.4 in staircase.glsl):
//                               levels 0, ⅓, ⅔, 1 over quarters of the band, with ramps, so the
//                               band shows grey steps inward ("too many bands")
//   RimOutline50x2(nv, r)       variation 3: SoftSilhouette(x) = saturate(50·x²), a fast smooth
//                               0 → 1 over 0.86 r < n·v < r
//   RimOutlineWeight(mode, nv, r) mode 0 threshold, 1 soft staircase, 2 50x²
// Numpy twin: app.sim.outline_metrics.rim_outline_weight (through app/sim/staircase.py).
//
// Failure cases: the thesis's own, kept — on large flat low-poly faces n·v is constant over the
// face, so a whole face crosses the band at once (half a table goes black, Fig. 135), and the
// bands of the staircase multiply on elongated surfaces (Fig. 137). Guarded: r is clamped to
// [1e-3, 1] (no division by zero); n·v is saturated, so a back-facing normal (n·v < 0) counts as
// the silhouette, not beyond it.
// =============================================================================================
#include "staircase.glsl"

const float RIM_STAIR_STEP = 1.0 / 3.0;

float RimCoordinate(float nv, float r) {
    return clamp(1.0 - clamp(nv, 0.0, 1.0) / clamp(r, 1e-3, 1.0), 0.0, 1.0);
}

// spec/003 §2.13 variation 1: the threshold, binary.
float RimOutlineThreshold(float nv, float r) {
    return ThresholdStep(RimCoordinate(nv, r), 0.0);
}

// spec/003 §2.13 variation 2: the soft staircase (spec/003 eq. 8.4 through SoftStairedValue).
float RimOutlineSoftStair(float nv, float r) {
    // x stretched by 1 + step so the band holds four levels, the top one (1) included
    float x = RimCoordinate(nv, r) * (1.0 + RIM_STAIR_STEP);
    return SoftStairedValue(x, RIM_STAIR_STEP, 0.5 * RIM_STAIR_STEP);
}

// spec/003 §2.13 variation 3: saturate(50·x²).
float RimOutline50x2(float nv, float r) { return SoftSilhouette(RimCoordinate(nv, r)); }

float RimOutlineWeight(int mode, float nv, float r) {
    if (mode == 0) return RimOutlineThreshold(nv, r);
    if (mode == 1) return RimOutlineSoftStair(nv, r);
    return RimOutline50x2(nv, r);
}
