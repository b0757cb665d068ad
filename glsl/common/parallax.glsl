// =============================================================================================
// Parallax mapping — spec/003 §2.3 (the thesis's §3.2; its CalculateBareParallaxTexcoords and
// the steep and occlusion searches of includes/BumpCommon and includes/UtilsBump.cginc). The
// texture coordinate is moved to where the view ray meets the height field, in tangent space.
//   v_tangent = M·v, M with rows t, b, n      spec/003 eq. 3.16, spec/003 eq. 3.17
//                                             (TangentSpaceView; v from the surface to the eye)
// One geometry for every method, the one the thesis adopts for steep parallax: the polygon is
// the top of the relief, height 1 (white) lies on it and height 0 (black) uParallaxScale below,
// in UV units. The view v is the unit tangent-space direction to the eye, v.z = sin(elevation).
//   1 bare       P = depth(A)·scale·v, O = P_xy, uv − O: the thesis's offset-limited form
//                spec/003 eq. 3.14, spec/003 eq. 3.15, with depth = 1 − height so that it meets
//                the other methods' geometry (the text's height(A)·v puts the polygon at the
//                bottom: the same picture slid by scale·v_xy); no division by v.z, so the offset
//                never exceeds the scale — and is too short at grazing angles, the thesis's
//                known failure
//   2 steep      n layers of thickness 1/n from height 1 down; each step moves one layer and
//                Δ = scale·v_xy/(v_z·n) in UV, and stops at the first layer the height field
//                is at or above (the thesis: "generally adequate to keep n between 10 and 20";
//                the layering shows at grazing angles, its "critical angle")
//   3 occlusion  the steep search, then the line between the last two samples: with
//                a = h_i − layer_i ≥ 0 and b = h_(i−1) − layer_(i−1) < 0 the UV is
//                mix(uv_i, uv_(i−1), a/(a − b)) (the weights the thesis names)
//   4 reference  beyond the thesis: the steep search with 1024 layers and 12 bisections of the
//                last interval — the ground truth the others are measured against
//   0 off        uv unchanged
// Heights are read from the height map's alpha (app/sim/surface_maps.py encode_height) with
// textureLod(…, 0): inside loops implicit derivatives are undefined. Numpy twin:
// app/sim/parallax.py (same sampling: bilinear, wrap; parallax_error measures each method
// against the reference in texels for the bench); tests/gl/test_shading_maps.py compares them.
//
// Failure cases guarded: v.z → 0 (grazing, or a view from below the surface) clamped to
// PARALLAX_MIN_VZ, so the steps and the offsets stay finite (at most scale/0.02 in UV); a zero
// view read as straight down the normal; layers clamped to [1, 256]; the search ends at layer 0,
// which every height meets, so a flat or all-black map gives uv − scale·v_xy/v_z and never a
// NaN; the occlusion weight's denominator is positive whenever there is a previous sample (a
// search that stops at once returns uv); layer heights computed as (n − i)/n, not accumulated,
// so the last layer is exactly 0.
// =============================================================================================
#include "bump.glsl"

uniform int uParallaxMode; // @param 1 [0, 4] §2.3 Parallax: 0 off, 1 bare (the thesis's inspector
                           // default), 2 steep, 3 occlusion, 4 reference (1024 layers and
                           // bisection, beyond the thesis)
uniform int uParallaxLayers; // @param 12 [1, 64] §2.3 layers n of steep and occlusion parallax (the
                             // thesis shows 12 and 32; keep 10–20)
uniform float uParallaxScale; // @param 0.05 [0, 0.2] step=0.005 §2.3 depth of the relief in UV
                              // units (height 0 lies this far below the surface)
// Specialisation (optional, as shadow.glsl's): a program compiled with PARALLAX_MODE defined
// reads it as a constant instead of uParallaxMode, so the methods it does not use (the
// reference's 1024 layers among them) are compiled out — a software rasteriser runs both sides
// of a branch on a uniform; the image is the same.
#ifdef PARALLAX_MODE
#define PARALLAX_MODE_VALUE PARALLAX_MODE
#else
#define PARALLAX_MODE_VALUE uParallaxMode
#endif

const float PARALLAX_MIN_VZ = 0.02;
const int PARALLAX_MAX_LAYERS = 256;
const int PARALLAX_REFERENCE_LAYERS = 1024;
const int PARALLAX_REFERENCE_BISECTIONS = 12;

// The tangent-space view of a world direction toEye through the frame [t b n] (bump.glsl).
vec3 TangentSpaceView(vec3 toEye, mat3 tbn) {
    // spec/003 eq. 3.16: M has rows t, b, n; spec/003 eq. 3.17: v_tangent = M·v
    return toEye * tbn;
}

float ParallaxHeight(sampler2D heightMap, vec2 uv) { return textureLod(heightMap, uv, 0.0).a; }

// The unit view, z kept at or above PARALLAX_MIN_VZ.
vec3 ParallaxView(vec3 viewTS) {
    float l = length(viewTS);
    vec3 v = l > 1e-12 ? viewTS / l : vec3(0.0, 0.0, 1.0);
    return vec3(v.xy, max(v.z, PARALLAX_MIN_VZ));
}

vec2 ParallaxBare(sampler2D heightMap, vec2 uv, vec3 v, float scale) {
    vec3 P = (1.0 - ParallaxHeight(heightMap, uv)) * scale * v;  // spec/003 eq. 3.14
    return uv - P.xy;  // spec/003 eq. 3.15
}

// The layer search: the first i in [0, n] with h(uv − i·Δ) ≥ (n − i)/n; returns i and, through
// a and b, h − layer at i and at i − 1 (b undefined when i = 0).
int ParallaxSearch(sampler2D heightMap, vec2 uv, vec2 delta, int n, out float a, out float b) {
    float h = ParallaxHeight(heightMap, uv);
    a = h - 1.0;
    b = 0.0;
    if (a >= 0.0) return 0;
    for (int i = 1; i <= n; ++i) {
        b = a;
        h = ParallaxHeight(heightMap, uv - float(i) * delta);
        a = h - float(n - i) / float(n);
        if (a >= 0.0) return i;
    }
    return n;  // not reached: layer 0 stops every search
}

vec2 ParallaxDelta(vec3 v, float scale, int n) { return scale * v.xy / (v.z * float(n)); }

vec2 ParallaxSteep(sampler2D heightMap, vec2 uv, vec3 v, float scale, int layers) {
    int n = clamp(layers, 1, PARALLAX_MAX_LAYERS);
    vec2 delta = ParallaxDelta(v, scale, n);
    float a, b;
    int i = ParallaxSearch(heightMap, uv, delta, n, a, b);
    return uv - float(i) * delta;
}

vec2 ParallaxOcclusion(sampler2D heightMap, vec2 uv, vec3 v, float scale, int layers) {
    int n = clamp(layers, 1, PARALLAX_MAX_LAYERS);
    vec2 delta = ParallaxDelta(v, scale, n);
    float a, b;
    int i = ParallaxSearch(heightMap, uv, delta, n, a, b);
    if (i == 0) return uv;
    vec2 cur = uv - float(i) * delta;
    return mix(cur, cur + delta, a / (a - b));
}

// The reference for the parallax methods (beyond the thesis): the steep search over
// PARALLAX_REFERENCE_LAYERS layers, then PARALLAX_REFERENCE_BISECTIONS bisections between the
// last layer above the height field and the first at or below it: the corrected uv.
// A search that stops at layer 0 (the eye ray meets the surface at once) returns uv.
vec2 ParallaxReference(sampler2D heightMap, vec2 uv, vec3 v, float scale) {
    int n = PARALLAX_REFERENCE_LAYERS;
    vec2 delta = ParallaxDelta(v, scale, n);
    float a, b;
    int i = ParallaxSearch(heightMap, uv, delta, n, a, b);
    if (i == 0) return uv;
    // bisect between (i − 1: above the height field) and (i: at or below it), in steps t
    float lo = float(i - 1), hi = float(i);
    for (int k = 0; k < PARALLAX_REFERENCE_BISECTIONS; ++k) {
        float mid = 0.5 * (lo + hi);
        if (ParallaxHeight(heightMap, uv - mid * delta) >= (float(n) - mid) / float(n)) {
            hi = mid;
        } else {
            lo = mid;
        }
    }
    return uv - 0.5 * (lo + hi) * delta;
}

// The parallax-corrected uv for the tangent-space view viewTS (from the surface to the eye),
// with uParallaxMode, uParallaxLayers and uParallaxScale.
vec2 ParallaxUV(sampler2D heightMap, vec2 uv, vec3 viewTS) {
    if (PARALLAX_MODE_VALUE <= 0) return uv;
    vec3 v = ParallaxView(viewTS);
    if (PARALLAX_MODE_VALUE == 1) return ParallaxBare(heightMap, uv, v, uParallaxScale);
    if (PARALLAX_MODE_VALUE == 2) {
        return ParallaxSteep(heightMap, uv, v, uParallaxScale, uParallaxLayers);
    }
    if (PARALLAX_MODE_VALUE == 3) {
        return ParallaxOcclusion(heightMap, uv, v, uParallaxScale, uParallaxLayers);
    }
    return ParallaxReference(heightMap, uv, v, uParallaxScale);
}
