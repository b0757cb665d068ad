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

// 1 = lit, 0 = in shadow; local = position in the local frame.
float ShadowVisibility(vec3 local, float bias) {
    if (!uShadowsEnabled) return 1.0;
    vec4 clip = uLightViewProj * vec4(local, 1.0);
    vec3 p = clip.xyz / clip.w * 0.5 + 0.5;
    if (any(lessThan(p, vec3(0.0))) || any(greaterThan(p, vec3(1.0)))) return 1.0;
    float depth = p.z - bias;
    if (!uShadowFiltered) return ShadowCompareNearest(uShadowMap, p.xy, depth);
    return ShadowPcf(uShadowMap, p.xy, depth);
}

// Cheap point visibility for the in-scattering integral's V(P) (light shafts): one bilinear
// comparison per sample.
float ShadowVisibilityPoint(vec3 local) {
    if (!uShadowsEnabled) return 1.0;
    vec4 clip = uLightViewProj * vec4(local, 1.0);
    vec3 p = clip.xyz / clip.w * 0.5 + 0.5;
    if (any(lessThan(p, vec3(0.0))) || any(greaterThan(p, vec3(1.0)))) return 1.0;
    return ShadowCompareBilinear(uShadowMap, p.xy, p.z - uShadowBias);
}
