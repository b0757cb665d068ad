// =============================================================================================
// Shadow receivers of every scene (spec/003 §2.8: Unity's directional, spot and point shadows,
// cascades, soft shadows; Fernando 2005's PCSS and Donnelly 2006's VSM beside them). The maps
// are made by app.render.shadow_maps with common/shadow_caster, which applies the normal and
// linear biases as Unity's caster does; this file only reads and compares them. Each light's
// visibility is 1 lit, 0 in full shadow. Numpy twins: app/sim/shadows.py and
// app/render/shadows.py (pcf_visibility).
// Specialisation: SHADOW_FILTER and SHADOW_TAPS, when defined, replace the filter and taps
// uniforms by constants (the block below the uniforms).
// Failure cases guarded: a point outside every map, past the shadow distance or of a disabled
// light is lit; maps are read on clamped texels, never wrapped; each function below names its
// own degenerate input and what it does then.
// =============================================================================================
#include "shadow_pcf.glsl"

// ---- the sun: its cascades share one depth atlas ----------------------------------------------
// uShadowSunMap holds 1 tile for 0 cascades, a 2 × 2 grid for 2 or 4. uShadowSunMatrix[c] maps
// a world point to atlas (u, v, depth); uShadowSunTile[c] is cascade c's uv rectangle, which
// every tap is clamped into, so a filter never reads the neighbouring cascade.
// The filters (uShadowSunFilter, uShadowSpotFilter): 0 hard, 1 the thesis's four-tap, 2 PCF,
// 3 PCSS, 4 VSM (ShadowFiltered). The taps (uShadow*Taps, the module's `<group>.shadow_taps`):
// 0 full, the reference; 1 fast, what `auto` picks on a software renderer; any other value
// reads as full.
uniform bool uShadowSunEnabled;
uniform sampler2D uShadowSunMap;       // depth atlas, compare off, NEAREST
uniform sampler2D uShadowSunMoments;   // (d, d²) atlas for VSM, LINEAR
uniform mat4 uShadowSunMatrix[4];
uniform vec4 uShadowSunTile[4];
uniform vec4 uShadowSunSplits;         // far view depth of each cascade
uniform int uShadowSunCascades;        // 1..4 maps in use
uniform int uShadowSunFilter;
uniform vec4 uShadowSunPcssScale;      // per cascade: texels of penumbra per unit d_r − d_b
uniform bool uShadowSunPcssFit;        // former sun penumbra ∝ (d_r − d_b)/d_b, fit-dependent
uniform int uShadowSunVsmBlur;
uniform float uShadowSunVsmBleed;
uniform float uShadowSunStrength;
uniform vec4 uShadowSunTexelWorld;     // per cascade: a texel's world size (metres)
uniform int uShadowSunTaps;            // 0 full, 1 fast

// ---- the spot: one perspective map ------------------------------------------------------------
uniform bool uShadowSpotEnabled;
uniform sampler2D uShadowSpotMap;
uniform sampler2D uShadowSpotMoments;
uniform mat4 uShadowSpotMatrix;
uniform int uShadowSpotFilter;
uniform float uShadowSpotPcssScale;
uniform int uShadowSpotVsmBlur;
uniform float uShadowSpotVsmBleed;
uniform float uShadowSpotStrength;
uniform float uShadowSpotTexelPerM;    // a texel's world size per metre from the light
uniform vec3 uShadowSpotPosition;
uniform int uShadowSpotTaps;

// ---- the point light: six faces in a 3 × 2 atlas of (|l| + bias)/range ------------------------
// Face f's matrix is uShadowPointFace[f]; its filter is at most the PCF.
uniform bool uShadowPointEnabled;
uniform sampler2D uShadowPointMap;     // 3 × 2 faces of (|l| + bias)/range, R of RG32F
uniform mat4 uShadowPointFace[6];
uniform vec3 uShadowPointPosition;
uniform float uShadowPointRange;
uniform int uShadowPointFilter;
uniform float uShadowPointStrength;
uniform float uShadowPointTexelPerM;
uniform int uShadowPointTaps;

// Specialisation (optional): a receiver compiled with SHADOW_FILTER (0..4: the sun's and the
// spot's filter, the point light's min(filter, 2)) and SHADOW_TAPS (0 or 1) reads them as
// constants instead of the uniforms, so the filters it does not use are compiled out and the
// taps' loops have constant bounds (app.render.shadow_maps.receiver_defines and
// receiver_variants). A software rasteriser runs both sides of a branch on a uniform, so this
// is where it saves; the image is the same.
#ifdef SHADOW_FILTER
#define SHADOW_SUN_FILTER SHADOW_FILTER
#define SHADOW_SPOT_FILTER SHADOW_FILTER
#define SHADOW_POINT_FILTER min(SHADOW_FILTER, 2)
#else
#define SHADOW_SUN_FILTER uShadowSunFilter
#define SHADOW_SPOT_FILTER uShadowSpotFilter
#define SHADOW_POINT_FILTER uShadowPointFilter
#endif
#ifdef SHADOW_TAPS
#define SHADOW_SUN_TAPS SHADOW_TAPS
#define SHADOW_SPOT_TAPS SHADOW_TAPS
#define SHADOW_POINT_TAPS SHADOW_TAPS
#else
#define SHADOW_SUN_TAPS uShadowSunTaps
#define SHADOW_SPOT_TAPS uShadowSpotTaps
#define SHADOW_POINT_TAPS uShadowPointTaps
#endif

const float SHADOW_GOLDEN_ANGLE = 2.39996323;  // radians, π (3 − √5): the disc's spiral step
const float SHADOW_TAN_85 = 11.43;             // tan 85°: the steepest receiver plane kept
const float SHADOW_DET_MIN = 1e-12;            // below it the map has no tangent plane
const float SHADOW_SCALE_MIN = 1e-12;          // uv per metre: floor of the map's scale
const float SHADOW_BLOCKER_MIN = 1e-4;         // smallest blocker depth PCSS divides by
const float SHADOW_VSM_VARIANCE_MIN = 1e-6;    // depth², VSM's variance floor (no 0/0)
const float SHADOW_VSM_BLEED_FLOOR = 1e-6;     // floor of 1 − bleed (bleed 1: no division by 0)
const float SHADOW_PENUMBRA_MIN = 0.5;         // texels: PCSS's narrowest tap spacing or radius
const float SHADOW_DISC_RADIUS_MAX = 16.0;     // texels: the sun's widest penumbra disc
const float SHADOW_PCF_SCALE_MAX = 8.0;        // texels: the spot's widest PCF tap spacing
const float SHADOW_SPOT_W_MIN = 1e-6;          // clip w below which a point is behind the spot
const float SHADOW_POINT_DIST_MIN = 1e-6;      // metres: a point this close to the light is lit
const float SHADOW_POINT_PCF_REACH = 3.0;      // texels: the point light's PCF reach (r 2 + 1)
const int SHADOW_VSM_BLUR_MAX = 4;             // texels, the widest VSM box blur radius

// The PCF's radius in texels for a taps setting: 1 (3 × 3, fast) or SHADOW_PCF_RADIUS (5 × 5,
// full, the reference). Any taps value other than 1 reads as full.
int ShadowPcfRadius(int taps) { return taps == 1 ? 1 : SHADOW_PCF_RADIUS; }

// The texel of `map` under uv ([0,1]² of the whole atlas), clamped into `tile` (its uv
// rectangle lo.xy, hi.zw), so that no tap wraps or reads the neighbouring tile.
ivec2 ShadowTexel(sampler2D map, vec2 uv, vec4 tile) {
    vec2 size = vec2(textureSize(map, 0));
    vec2 lo = tile.xy * size, hi = tile.zw * size - 1.0;
    return ivec2(clamp(floor(uv * size), lo, hi));
}

// One hard comparison: 1 (lit) where the reference depth is at most the stored one ([0,1]
// depths, or distances over range for the point light).
float ShadowHardAt(sampler2D map, vec2 uv, float depth, vec4 tile) {
    return step(depth, texelFetch(map, ShadowTexel(map, uv, tile), 0).r);
}

// The bilinear blend of the four hard comparisons around uv, the hardware's compare-mode read
// done by hand on a sampler2D; every texel clamped into the tile.
float ShadowBilinearAt(sampler2D map, vec2 uv, float depth, vec4 tile) {
    vec2 size = vec2(textureSize(map, 0));
    vec2 st = uv * size - 0.5;
    vec2 f = fract(st);
    vec2 t = 1.0 / size;
    vec2 base = (floor(st) + 0.5) * t;
    float s00 = ShadowHardAt(map, base, depth, tile);
    float s10 = ShadowHardAt(map, base + vec2(t.x, 0.0), depth, tile);
    float s01 = ShadowHardAt(map, base + vec2(0.0, t.y), depth, tile);
    float s11 = ShadowHardAt(map, base + t, depth, tile);
    return mix(mix(s00, s10, f.x), mix(s01, s11, f.x), f.y);
}

// The Gaussian PCF of shadow_pcf.glsl of radius r, its taps `scale` texels apart and kept in
// the tile: (2 r + 1)² bilinear comparisons. PCSS's, whose scale varies; the weights are
// normalised by their sum, so the result stays in [0,1].
float ShadowPcfAt(sampler2D map, vec2 uv, float depth, vec4 tile, float scale, int r) {
    vec2 t = scale / vec2(textureSize(map, 0));
    float sum = 0.0, wsum = 0.0;
    for (int y = -r; y <= r; ++y) {
        for (int x = -r; x <= r; ++x) {
            float w = ShadowPcfWeight(x, y);
            sum += w * ShadowBilinearAt(map, uv + vec2(x, y) * t, depth, tile);
            wsum += w;
        }
    }
    return sum / wsum;
}

// The weight of texel k (−r … r + 1 from the base texel) along one axis in the unit-scale PCF
// of radius r with the bilinear fraction f: tap k reads it with weight 1 − f, tap k − 1 with
// weight f; g and gPrev are the Gaussian's weights of k and k − 1 (0 outside −r … r).
float ShadowPcfAxisWeight(float g, float gPrev, float f) { return g * (1.0 - f) + gPrev * f; }

// The PCF's unnormalised Gaussian weight of tap k along one axis, exp(−k²/(2σ²)), σ in texels;
// 0 past the radius r.
float ShadowPcfGauss(int k, int r) {
    return abs(k) > r ? 0.0 : exp(-0.5 * float(k * k) / (SHADOW_PCF_SIGMA * SHADOW_PCF_SIGMA));
}

// ShadowPcfAt at scale 1, exactly, from the (2 r + 2)² texels its taps read: each texel's
// weight is the sum over the taps that read it of the tap's Gaussian weight times its bilinear
// weight, and the Gaussian is separable, so that weight is the product of two axis weights.
// 36 reads replace 100 for the same value (r = 2). The filter of the PCF mode and of the
// point light; texel indices are clamped into the tile.
float ShadowPcfBlock(sampler2D map, vec2 uv, float depth, vec4 tile, int r) {
    vec2 size = vec2(textureSize(map, 0));
    vec2 st = uv * size - 0.5;
    vec2 f = fract(st);
    vec2 b = floor(st);
    vec2 lo = tile.xy * size, hi = tile.zw * size - 1.0;
    float sum = 0.0, wsum = 0.0;
    float gyPrev = 0.0;
    for (int y = -r; y <= r + 1; ++y) {
        float gy = ShadowPcfGauss(y, r);
        float wy = ShadowPcfAxisWeight(gy, gyPrev, f.y);
        gyPrev = gy;
        float ty = clamp(b.y + float(y), lo.y, hi.y);
        float gxPrev = 0.0;
        for (int x = -r; x <= r + 1; ++x) {
            float gx = ShadowPcfGauss(x, r);
            float w = wy * ShadowPcfAxisWeight(gx, gxPrev, f.x);
            gxPrev = gx;
            ivec2 texel = ivec2(clamp(b.x + float(x), lo.x, hi.x), ty);
            sum += w * step(depth, texelFetch(map, texel, 0).r);
            wsum += w;
        }
    }
    return sum / wsum;
}

// The thesis's four-tap filter (spec/003 §2.8): the mean of the hard comparisons at the four
// diagonal neighbours, one texel away, of uv.
float ShadowFourTap(sampler2D map, vec2 uv, float depth, vec4 tile) {
    vec2 t = 1.0 / vec2(textureSize(map, 0));
    return 0.25 * (ShadowHardAt(map, uv + vec2(-t.x, -t.y), depth, tile)
                   + ShadowHardAt(map, uv + vec2(t.x, -t.y), depth, tile)
                   + ShadowHardAt(map, uv + vec2(-t.x, t.y), depth, tile)
                   + ShadowHardAt(map, uv + vec2(t.x, t.y), depth, tile));
}

// One texel of the receiver's plane (slope: depth per uv), in depth units, taken off every
// tap's depth: a tap's bilinear comparison reads texels up to one texel from where the plane
// was evaluated, and the stored depth is constant over a texel (the caster's biases cover one
// comparison at the centre only).
float ShadowPlaneSlack(vec2 slope, vec2 mapSize) { return dot(abs(slope), 1.0 / mapSize); }

// The light's disc over the map: the mean of SHADOW_PCSS_DISC bilinear comparisons on a
// Fibonacci spiral of `radius` texels (tap k at radius √((k + ½)/N), angle k × the golden
// angle: equal areas of the disc), each against the receiver's plane (`slope`). The visibility
// of a disc light behind a blocker at one depth. Numpy twin: app.sim.shadows.disc_taps.
#define SHADOW_PCSS_DISC 32
float ShadowDiscAt(sampler2D map, vec2 uv, float depth, vec4 tile, float radius, vec2 slope) {
    vec2 t = radius / vec2(textureSize(map, 0));
    float slack = ShadowPlaneSlack(slope, vec2(textureSize(map, 0)));
    float sum = 0.0;
    for (int k = 0; k < SHADOW_PCSS_DISC; ++k) {
        float r = sqrt((float(k) + 0.5) / float(SHADOW_PCSS_DISC));
        float a = float(k) * SHADOW_GOLDEN_ANGLE;
        vec2 o = r * vec2(cos(a), sin(a)) * t;
        sum += ShadowBilinearAt(map, uv + o, depth + dot(slope, o) - slack, tile);
    }
    return sum / float(SHADOW_PCSS_DISC);
}

// The receiver's plane in the map (receiver-plane depth bias, Isidoro 2006): d depth / d uv of
// the plane through worldPos (metres) with this normal, so a tap at uv + o compares the
// receiver's own depth there, depth + slope · o, and a wide kernel over a sloped receiver
// neither shadows it nor counts it as a blocker. Failure cases: a receiver edge-on to the sun
// (which the sun barely lights) has its slope capped at that of a plane 85° from facing the
// light; a degenerate one (no tangent plane in the map, |det| < SHADOW_DET_MIN) gets none.
vec2 ShadowReceiverSlope(mat4 m, vec3 worldPos, vec3 worldNormal) {
    vec3 n = normalize(worldNormal);
    vec3 t1 = normalize(cross(n, abs(n.y) < 0.9 ? vec3(0.0, 1.0, 0.0) : vec3(1.0, 0.0, 0.0)));
    vec3 t2 = cross(n, t1);
    vec4 h0 = m * vec4(worldPos, 1.0);
    vec4 h1 = m * vec4(worldPos + t1, 1.0);
    vec4 h2 = m * vec4(worldPos + t2, 1.0);
    vec3 a = h1.xyz / h1.w - h0.xyz / h0.w;
    vec3 b = h2.xyz / h2.w - h0.xyz / h0.w;
    mat2 j = mat2(a.xy, b.xy);
    float det = determinant(j);
    if (abs(det) < SHADOW_DET_MIN) return vec2(0.0);
    vec2 slope = vec2(a.z, b.z) * inverse(j);
    // a 45° plane's slope is (depth per metre) / (uv per metre): the matrix's rows' scales
    float perMetreUv = length(vec3(m[0][0], m[1][0], m[2][0]));
    float perMetreDepth = length(vec3(m[0][2], m[1][2], m[2][2]));
    float cap = SHADOW_TAN_85 * perMetreDepth / max(perMetreUv, SHADOW_SCALE_MIN);
    float len = length(slope);
    return len > cap ? slope * (cap / len) : slope;
}

// PCSS (Fernando 2005): a 7 × 7 blocker search in 2-texel steps (fast taps: 4 × 4 in 4-texel
// steps over the same ±6 texels), then a filter as wide as the penumbra, in texels, from the
// blocker's depth d_b and the receiver's d_r (`depth`):
// - a perspective map (the spot, a light of finite size): d_b the mean blocker,
//   w = pcssScale (d_r − d_b) / d_b, the 5 × 5 Gaussian PCF at that width (0.5..8 texels per
//   tap) whatever the taps (fewer taps spread that far apart band the penumbra);
// - an orthographic one (`parallel`: the sun, a light of angular radius θ at infinity, depths
//   linear in metres): d_b the blocker nearest the receiver (the silhouette that bounds the
//   penumbra: the mean of every blocker in the window includes a convex caster's lit top and
//   widened the spheres' penumbra by 29 % on the surfaces lab's floor), w = pcssScale
//   (d_r − d_b), the disc the light's cone cuts at the blocker's depth, of radius
//   (d_r − d_b) tan θ in world units: ShadowDiscAt of radius w / 2 (0.5..16 texels), every tap
//   against the receiver's plane (`slope`). So the penumbra does not depend on how the
//   orthographic map is fitted, and its profile is the disc's.
// Failure cases: no blocker in the window is lit (1); d_b is floored at SHADOW_BLOCKER_MIN
// before dividing.
float ShadowPcss(sampler2D map, vec2 uv, float depth, vec4 tile, float pcssScale, int taps,
                 bool parallel, vec2 slope) {
    vec2 t = 1.0 / vec2(textureSize(map, 0));
    float slack = ShadowPlaneSlack(slope, vec2(textureSize(map, 0)));
    float sum = 0.0, count = 0.0;
    int n = taps == 1 ? 4 : 7;
    float spacing = taps == 1 ? 4.0 : 2.0;
    float first = -0.5 * float(n - 1) * spacing;
    for (int y = 0; y < n; ++y) {
        for (int x = 0; x < n; ++x) {
            vec2 o = vec2(first) + spacing * vec2(x, y);
            float d = texelFetch(map, ShadowTexel(map, uv + o * t, tile), 0).r;
            if (d < depth + dot(slope, o * t) - slack) {
                sum = parallel ? max(sum, d) : sum + d;
                count += 1.0;
            }
        }
    }
    if (count < 0.5) return 1.0;
    float blocker = parallel ? sum : sum / count;
    float w = pcssScale * (depth - blocker)
              / (parallel ? 1.0 : max(blocker, SHADOW_BLOCKER_MIN));
    if (parallel) {
        float radius = clamp(0.5 * w, SHADOW_PENUMBRA_MIN, SHADOW_DISC_RADIUS_MAX);
        return ShadowDiscAt(map, uv, depth, tile, radius, slope);
    }
    float scale = clamp(w / float(2 * SHADOW_PCF_RADIUS), SHADOW_PENUMBRA_MIN,
                        SHADOW_PCF_SCALE_MAX);
    return ShadowPcfAt(map, uv, depth, tile, scale, SHADOW_PCF_RADIUS);
}

// Variance shadow maps (Donnelly and Lauritzen 2006): the moments (d, d²) averaged over a box
// of radius `blur` texels (0..SHADOW_VSM_BLUR_MAX), then Chebyshev's upper bound
// σ² / (σ² + (d_r − μ)²) on the lit fraction, with light-bleeding reduction: the bound's lowest
// `bleed` ([0,1)) cut off and the rest rescaled to [0,1]. Failure cases: the variance is floored
// (no 0/0 on a flat caster) and so is 1 − bleed; a receiver in front of the mean is lit.
float ShadowVsm(sampler2D moments, vec2 uv, float depth, vec4 tile, int blur, float bleed) {
    vec2 size = vec2(textureSize(moments, 0));
    vec2 t = 1.0 / size;
    vec2 lo = tile.xy + 0.5 * t, hi = tile.zw - 0.5 * t;
    vec2 m = vec2(0.0);
    float n = 0.0;
    int r = clamp(blur, 0, SHADOW_VSM_BLUR_MAX);
    for (int y = -r; y <= r; ++y) {
        for (int x = -r; x <= r; ++x) {
            m += texture(moments, clamp(uv + vec2(x, y) * t, lo, hi)).rg;
            n += 1.0;
        }
    }
    m /= n;
    float d = depth - m.x;
    if (d <= 0.0) return 1.0;
    float variance = max(m.y - m.x * m.x, SHADOW_VSM_VARIANCE_MIN);
    float p = variance / (variance + d * d);
    return clamp((p - bleed) / max(1.0 - bleed, SHADOW_VSM_BLEED_FLOOR), 0.0, 1.0);
}

// How many texels a filter reaches from its centre: the receiver moves that many texels along
// its normal before comparing (normal-offset shadows), so a wide kernel over a sloped receiver
// does not shadow the receiver itself (the casters' biases are sized for one comparison).
float ShadowFilterReach(int mode, int blur) {
    if (mode == 1) return 1.0;
    if (mode == 2 || mode == 3) return float(SHADOW_PCF_RADIUS) + 1.0;
    if (mode == 4) return float(blur) + 1.0;
    return 0.0;
}

// The visibility of map point c (uv, depth) by filter `mode`: 0 hard (one compare), 1 the
// thesis's four-tap, 2 PCF (shadow_pcf.glsl's Gaussian: 5 × 5, or 3 × 3 with fast taps),
// 3 PCSS, 4 VSM (moments, blur radius in texels, bleed reduction). An unknown mode is hard.
float ShadowFiltered(sampler2D map, sampler2D moments, vec3 c, vec4 tile, int mode,
                     float pcssScale, int blur, float bleed, int taps, bool parallel,
                     vec2 slope) {
    if (mode == 1) return ShadowFourTap(map, c.xy, c.z, tile);
    if (mode == 2) return ShadowPcfBlock(map, c.xy, c.z, tile, ShadowPcfRadius(taps));
    if (mode == 3) return ShadowPcss(map, c.xy, c.z, tile, pcssScale, taps, parallel, slope);
    if (mode == 4) return ShadowVsm(moments, c.xy, c.z, tile, blur, bleed);
    return ShadowHardAt(map, c.xy, c.z, tile);
}

// Whether map point c lies in the tile's uv rectangle and the map's [0,1] depth range
// (outside: the map says nothing, and the caller lights the point).
bool ShadowInside(vec3 c, vec4 tile) {
    return all(greaterThanEqual(c.xy, tile.xy)) && all(lessThanEqual(c.xy, tile.zw))
        && c.z >= 0.0 && c.z <= 1.0;
}

// The sun's cascade of a point at view depth viewDepth (metres), −1 past the shadow distance.
// A zero-size cascade (all splits equal) is skipped, the last one taking the point.
int ShadowCascade(float viewDepth) {
    for (int i = 0; i < 4; ++i) {
        if (i >= uShadowSunCascades) break;
        if (viewDepth <= uShadowSunSplits[i]) return i;
    }
    return -1;
}

// The sun's visibility at worldPos (metres) with unit worldNormal, at view depth viewDepth
// (metres), in [0,1] after uShadowSunStrength: mix(1, v, strength). Lit (1) when the sun's
// shadows are off, past the shadow distance, or outside the cascade's tile.
float ShadowSun(vec3 worldPos, vec3 worldNormal, float viewDepth) {
    if (!uShadowSunEnabled) return 1.0;
    int c = ShadowCascade(viewDepth);
    if (c < 0) return 1.0;
    // the sun's PCSS follows the receiver's plane (no normal offset: it would shift the
    // penumbra); every other filter moves the receiver along its normal
    bool plane = SHADOW_SUN_FILTER == 3 && !uShadowSunPcssFit;
    vec3 offset = plane ? vec3(0.0) : worldNormal * uShadowSunTexelWorld[c]
                * ShadowFilterReach(SHADOW_SUN_FILTER, uShadowSunVsmBlur);
    vec4 h = uShadowSunMatrix[c] * vec4(worldPos + offset, 1.0);
    vec3 p = h.xyz / h.w;
    vec4 tile = uShadowSunTile[c];
    if (!ShadowInside(p, tile)) return 1.0;
    vec2 slope = plane ? ShadowReceiverSlope(uShadowSunMatrix[c], worldPos, worldNormal)
                       : vec2(0.0);
    float v = ShadowFiltered(uShadowSunMap, uShadowSunMoments, p, tile, SHADOW_SUN_FILTER,
                             uShadowSunPcssScale[c], uShadowSunVsmBlur, uShadowSunVsmBleed,
                             SHADOW_SUN_TAPS, !uShadowSunPcssFit, slope);
    return mix(1.0, v, clamp(uShadowSunStrength, 0.0, 1.0));
}

// The spot's visibility at worldPos (metres), in [0,1] after uShadowSpotStrength; the normal
// offset grows with the distance to the light (a perspective map's texel does). Lit when off,
// behind the light (clip w ≤ SHADOW_SPOT_W_MIN) or outside its map.
float ShadowSpot(vec3 worldPos, vec3 worldNormal) {
    if (!uShadowSpotEnabled) return 1.0;
    vec3 offset = worldNormal * uShadowSpotTexelPerM * length(worldPos - uShadowSpotPosition)
                * ShadowFilterReach(SHADOW_SPOT_FILTER, uShadowSpotVsmBlur);
    vec4 h = uShadowSpotMatrix * vec4(worldPos + offset, 1.0);
    if (h.w <= SHADOW_SPOT_W_MIN) return 1.0;
    vec3 p = h.xyz / h.w;
    vec4 tile = vec4(0.0, 0.0, 1.0, 1.0);
    if (!ShadowInside(p, tile)) return 1.0;
    float v = ShadowFiltered(uShadowSpotMap, uShadowSpotMoments, p, tile, SHADOW_SPOT_FILTER,
                             uShadowSpotPcssScale, uShadowSpotVsmBlur, uShadowSpotVsmBleed,
                             SHADOW_SPOT_TAPS, false, vec2(0.0));
    return mix(1.0, v, clamp(uShadowSpotStrength, 0.0, 1.0));
}

// The face of the cube a direction leaves by: +x −x +y −y +z −z = 0..5.
int ShadowCubeFace(vec3 d) {
    vec3 a = abs(d);
    if (a.x >= a.y && a.x >= a.z) return d.x >= 0.0 ? 0 : 1;
    if (a.y >= a.z) return d.y >= 0.0 ? 2 : 3;
    return d.z >= 0.0 ? 4 : 5;
}

// The point light's visibility at worldPos (metres), in [0,1] after uShadowPointStrength: the
// distance over range compared in the face the direction leaves by (hard, four-tap or PCF).
// Lit when off, with no range, past the range, or exactly at the light (no direction).
float ShadowPoint(vec3 worldPos, vec3 worldNormal) {
    if (!uShadowPointEnabled || uShadowPointRange <= 0.0) return 1.0;
    int mode = SHADOW_POINT_FILTER;
    float reach = mode == 0 ? 0.0 : (mode == 1 ? 1.0 : SHADOW_POINT_PCF_REACH);
    worldPos += worldNormal * reach * uShadowPointTexelPerM
                * length(worldPos - uShadowPointPosition);
    vec3 l = worldPos - uShadowPointPosition;
    float dist = length(l);
    if (dist < SHADOW_POINT_DIST_MIN || dist >= uShadowPointRange) return 1.0;
    int f = ShadowCubeFace(l);
    vec4 h = uShadowPointFace[f] * vec4(worldPos, 1.0);
    vec2 uv = h.xy / h.w;
    vec4 tile = vec4(float(f % 3) / 3.0, float(f / 3) / 2.0,
                     float(f % 3 + 1) / 3.0, float(f / 3 + 1) / 2.0);
    float ref = dist / uShadowPointRange;
    float v;
    if (mode == 0) v = ShadowHardAt(uShadowPointMap, uv, ref, tile);
    else if (mode == 1) v = ShadowFourTap(uShadowPointMap, uv, ref, tile);
    else v = ShadowPcfBlock(uShadowPointMap, uv, ref, tile, ShadowPcfRadius(SHADOW_POINT_TAPS));
    return mix(1.0, v, clamp(uShadowPointStrength, 0.0, 1.0));
}
