// =============================================================================================
// Sun visibility from the static orthographic shadow map (spec/002 §3.1–3.2): rendered from the
// sun only when the light direction changes; V(P) = 0 where P is deeper than the stored depth.
// Filtering (§3.2, "processing the map"): the shared percentage-closer filter of
// common/shadow_pcf.glsl — a Gaussian-weighted neighbourhood (5×5, σ = 1 texel) of bilinear
// depth comparisons, the variant the thesis kept — or a single nearest comparison.
// The comparisons are the hardware's (uShadowMap a sampler2DShadow, compare mode '<=', LINEAR:
// one read per bilinear comparison, 25 per filtered pixel); with SHADOW_COMPARE_MANUAL defined
// the map is a plain sampler2D (compare mode off) and each comparison is four texelFetch and a
// blend (100 reads), the earlier path, kept selectable (planet.shadow_compare = manual) for the
// bench's comparison: the two agree within float rounding.
// Points outside the map's box are lit. A slope-scaled bias avoids self-shadowing acne.
// Where a caster may be: the map holds only the mountains and the city, so a point is lit —
// exactly, by the comparisons themselves — unless its light-space (x, y) falls within the
// casters' footprint (their vertices' bounds, padded by the filter's reach) and it lies deeper
// than the nearest caster; uShadowCasterBox and uShadowCasterDepth (from the CPU, once per sun
// direction) say where. ShadowVisibility reads the map only there (the filter's taps are a loop
// whose count is zero elsewhere: a software rasteriser runs every branch of a shader but stops a
// loop no pixel of a block needs), and ShadowSampleRange gives the light shafts the view-ray
// samples that may be in shadow, so samples elsewhere read nothing. The image is the same.
// Failure cases: see common/shadow_pcf.glsl (edge clamping, negative reference depths); points
// outside the light's box are lit rather than compared against a clamped edge texel.
// =============================================================================================
#include "shadow_pcf.glsl"

#ifdef SHADOW_COMPARE_MANUAL
uniform sampler2D uShadowMap;        // depth in [0, 1], orthographic from the sun; compare off
#else
uniform sampler2DShadow uShadowMap;  // the same map, compare mode '<=', LINEAR
#endif
uniform mat4 uLightViewProj;    // local frame → light clip space
uniform bool uShadowFiltered;   // Gaussian + bilinear (true) or nearest, unfiltered (false)
uniform float uShadowBias;      // in depth units
uniform bool uShadowsEnabled;
uniform vec4 uShadowCasterBox;    // light-space (x0, y0, x1, y1) in [0, 1] of the casters, padded
uniform float uShadowCasterDepth; // light-space depth in [0, 1] of the nearest caster
#define SHADOW_PCF_TAPS ((2 * SHADOW_PCF_RADIUS + 1) * (2 * SHADOW_PCF_RADIUS + 1))

// Light-space position in [0, 1]³ of a point of the local frame (orthographic: w = 1).
vec3 ShadowLightCoords(vec3 local) {
    vec4 clip = uLightViewProj * vec4(local, 1.0);
    return clip.xyz / clip.w * 0.5 + 0.5;
}

// True where a caster may hide the sun from the light-space point p (false: lit, exactly).
bool ShadowMayBeShadowed(vec3 p) {
    return all(greaterThanEqual(p, vec3(uShadowCasterBox.xy, uShadowCasterDepth)))
        && all(lessThanEqual(p.xy, uShadowCasterBox.zw));
}

// The shared filter (common/shadow_pcf.glsl's ShadowPcf: the same taps, weights, order and
// sums) as one loop of `taps` iterations: SHADOW_PCF_TAPS, or 0 where nothing can shadow the
// point. Nothing in it may bound the trip count at compile time (no array indexed by k): a
// compiler that can bound it unrolls the loop, and every unrolled tap then runs everywhere.
float ShadowPcfTaps(vec2 uv, float depth, int taps) {
    vec2 texelSize = 1.0 / vec2(textureSize(uShadowMap, 0));
    const int side = 2 * SHADOW_PCF_RADIUS + 1;
    float sum = 0.0, wsum = 0.0;
    for (int k = 0; k < taps; ++k) {
        int y = k / side - SHADOW_PCF_RADIUS;
        int x = k - (y + SHADOW_PCF_RADIUS) * side - SHADOW_PCF_RADIUS;
        float w = ShadowPcfWeight(x, y);
        sum += w * ShadowCompareBilinear(uShadowMap, uv + vec2(x, y) * texelSize, depth);
        wsum += w;
    }
    return taps > 0 ? sum / wsum : 1.0;
}

// 1 = lit, 0 = in shadow; local = position in the local frame.
float ShadowVisibility(vec3 local, float bias) {
    if (!uShadowsEnabled) return 1.0;
    vec3 p = ShadowLightCoords(local);
    if (any(lessThan(p, vec3(0.0))) || any(greaterThan(p, vec3(1.0)))) return 1.0;
    float depth = p.z - bias;
    if (!uShadowFiltered) return ShadowCompareNearest(uShadowMap, p.xy, depth);
    return ShadowPcfTaps(p.xy, depth, ShadowMayBeShadowed(p) ? SHADOW_PCF_TAPS : 0);
}

// Cheap point visibility for the in-scattering integral's V(P) (light shafts): one bilinear
// comparison per sample.
float ShadowVisibilityPoint(vec3 local) {
    if (!uShadowsEnabled) return 1.0;
    vec3 p = ShadowLightCoords(local);
    if (any(lessThan(p, vec3(0.0))) || any(greaterThan(p, vec3(1.0)))) return 1.0;
    return ShadowCompareBilinear(uShadowMap, p.xy, p.z - uShadowBias);
}

// The samples i ∈ [first, last) of a view ray's midpoint sum (t_i = t0 + (i + ½) ds, i < n, the
// ray from the camera at `camera` in the local frame along dir) whose points may be in shadow:
// the ray's light-space line p(t) = p(0) + t · M dir / 2 clipped to the casters' box extended
// to the far plane (a slab test), widened by one sample each side against rounding. (0, 0)
// when shadows are off or the ray misses the box.
ivec2 ShadowSampleRange(vec3 camera, vec3 dir, float t0, float ds, int n) {
    if (!uShadowsEnabled || !(ds > 0.0)) return ivec2(0);
    vec3 a = ShadowLightCoords(camera);
    vec3 b = 0.5 * (mat3(uLightViewProj) * dir);
    b = mix(b, vec3(1.0e-30), lessThan(abs(b), vec3(1.0e-30)));   // no division by zero
    vec3 lo = (vec3(uShadowCasterBox.xy, uShadowCasterDepth) - a) / b;
    vec3 hi = (vec3(uShadowCasterBox.zw, 1.0) - a) / b;
    vec3 near = min(lo, hi), far = max(lo, hi);
    float enter = max(max(near.x, near.y), near.z);
    float leave = min(min(far.x, far.y), far.z);
    if (!(leave >= enter)) return ivec2(0);
    float fn = float(n);
    float first = clamp(floor((enter - t0) / ds - 0.5) - 1.0, 0.0, fn);
    float last = clamp(ceil((leave - t0) / ds - 0.5) + 2.0, first, fn);
    return ivec2(int(first), int(last));
}
