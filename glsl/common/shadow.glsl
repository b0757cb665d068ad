// =============================================================================================
// Shadow receivers of every scene (spec/003 §2.8: Unity's directional, spot and point shadows,
// cascades, soft shadows; PCSS and VSM beside them). The maps are made by
// app.render.shadow_maps with common/shadow_caster (which applies the normal and linear biases,
// as Unity's caster does); this file only compares. Numpy twin: app/sim/shadows.py (hard,
// four_tap, pcss_penumbra, pcss_penumbra_parallel, disc_taps, chebyshev, point_encode) and
// app/render/shadows.py (pcf_visibility).
//
// Layout: the sun's cascades share one depth atlas (uShadowSunMap; 1 tile for 0 cascades, a
// 2 × 2 grid for 2 or 4): uShadowSunMatrix[c] maps a world point to atlas (u, v, depth) and
// uShadowSunTile[c] is the tile's uv rectangle, which every tap is clamped into (a filter never
// reads the neighbouring cascade). A point light's six faces lie in a 3 × 2 atlas of
// (|l| + bias)/range (colour, uShadowPointMap), face f's matrix uShadowPointFace[f].
// uShadowSunFilter / uShadowSpotFilter: 0 hard (one compare), 1 the thesis's four-tap (the mean
// of the four diagonal neighbours), 2 PCF (shadow_pcf.glsl's Gaussian), 3 PCSS (blocker search,
// a PCF as wide as the penumbra: Fernando 2005's w = w_light (d_r − d_b) / d_b for the spot,
// the Gaussian PCF at that width; for the sun, a light of angular radius θ at infinity, the
// disc the light's cone cuts from the blocker's depth, radius (d_r − d_b) tan θ in world
// units, averaged over SHADOW_PCSS_DISC taps: so the penumbra does not depend on how the
// orthographic map is fitted, and its profile is the disc's), 4 VSM
// (moments, a box blur of radius uShadow*VsmBlur texels, Chebyshev with light-bleeding
// reduction uShadow*VsmBleed).
//
//
// Taps (uShadow*Taps, the module's `<group>.shadow_taps`): 0 full — the PCF's 5 × 5 Gaussian
// (SHADOW_PCF_RADIUS 2) and PCSS's 7 × 7 blocker search, the reference; 1 fast — a 3 × 3
// Gaussian for the PCF and the point light, a 4 × 4 search over the same ±6 texels for PCSS
// (what `auto` picks on a software renderer). At its unit scale (the PCF filter, the point light) the Gaussian of bilinear
// comparisons is summed exactly as one (2 r + 2)² block of texels with separable weights
// (ShadowPcfBlock): each texel's weight is the sum over the taps that read it of the tap's
// Gaussian weight times its bilinear weight, so 36 reads replace 100 for the same value.
//
// Specialisation (optional): a receiver compiled with SHADOW_FILTER (0..4: the sun's and the
// spot's filter, the point light's min(filter, 2)) and SHADOW_TAPS (0 or 1) defined reads them
// as constants instead of uShadow*Filter and uShadow*Taps, so the filters it does not use are
// compiled out and the taps' loops have constant bounds (app.render.shadow_maps
// .receiver_defines and receiver_variants). A software rasteriser runs both sides of a branch
// on a uniform, so this is where it saves; the image is the same.
//
// Failure cases guarded: a point outside every map (or past the shadow distance) is lit; a
// disabled light returns 1; maps are read with texelFetch on clamped indices (no wrap); the
// VSM variance is floored (no 0/0); a zero-size cascade (all splits equal) is skipped by the
// cascade search, the last cascade taking the point; a point exactly at a point light is lit;
// a taps value other than 1 reads as full; a receiver edge-on to the sun has its plane's slope
// capped (ShadowReceiverSlope) and a degenerate one (no tangent plane in the map) none.
// =============================================================================================
#include "shadow_pcf.glsl"

uniform bool uShadowSunEnabled;
uniform sampler2D uShadowSunMap;       // depth atlas, compare off, NEAREST
uniform sampler2D uShadowSunMoments;   // (d, d²) atlas for VSM, LINEAR
uniform mat4 uShadowSunMatrix[4];
uniform vec4 uShadowSunTile[4];
uniform vec4 uShadowSunSplits;         // far view depth of each cascade
uniform int uShadowSunCascades;        // 1..4 maps in use
uniform int uShadowSunFilter;
uniform vec4 uShadowSunPcssScale;      // per cascade: texels of penumbra per unit d_r − d_b
uniform bool uShadowSunPcssFit;        // the former sun penumbra, ∝ (d_r − d_b)/d_b (fit-dependent)
uniform int uShadowSunVsmBlur;
uniform float uShadowSunVsmBleed;
uniform float uShadowSunStrength;
uniform vec4 uShadowSunTexelWorld;     // per cascade: a texel's world size (metres)
uniform int uShadowSunTaps;            // 0 full, 1 fast

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

uniform bool uShadowPointEnabled;
uniform sampler2D uShadowPointMap;     // 3 × 2 faces of (|l| + bias)/range, R of RG32F
uniform mat4 uShadowPointFace[6];
uniform vec3 uShadowPointPosition;
uniform float uShadowPointRange;
uniform int uShadowPointFilter;
uniform float uShadowPointStrength;
uniform float uShadowPointTexelPerM;
uniform int uShadowPointTaps;

// The specialised constants, or the uniforms (see the header).
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

// The PCF's radius of a taps setting: the thesis-independent 5 × 5 reference (SHADOW_PCF_RADIUS)
// or 3 × 3.
int ShadowPcfRadius(int taps) { return taps == 1 ? 1 : SHADOW_PCF_RADIUS; }

ivec2 ShadowTexel(sampler2D map, vec2 uv, vec4 tile) {
    vec2 size = vec2(textureSize(map, 0));
    vec2 lo = tile.xy * size, hi = tile.zw * size - 1.0;
    return ivec2(clamp(floor(uv * size), lo, hi));
}

float ShadowHardAt(sampler2D map, vec2 uv, float depth, vec4 tile) {
    return step(depth, texelFetch(map, ShadowTexel(map, uv, tile), 0).r);
}

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

// The Gaussian PCF of shadow_pcf.glsl of radius r, its taps scaled by `scale` texels and kept
// in the tile: (2 r + 1)² bilinear comparisons (PCSS's, whose scale varies).
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

float ShadowPcfGauss(int k, int r) {
    return abs(k) > r ? 0.0 : exp(-0.5 * float(k * k) / (SHADOW_PCF_SIGMA * SHADOW_PCF_SIGMA));
}

// ShadowPcfAt at scale 1, exactly, from the (2 r + 2)² texels its taps read (the header): the
// Gaussian is separable, so each texel's weight is the product of its two axis weights.
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

float ShadowFourTap(sampler2D map, vec2 uv, float depth, vec4 tile) {
    vec2 t = 1.0 / vec2(textureSize(map, 0));
    return 0.25 * (ShadowHardAt(map, uv + vec2(-t.x, -t.y), depth, tile)
                   + ShadowHardAt(map, uv + vec2(t.x, -t.y), depth, tile)
                   + ShadowHardAt(map, uv + vec2(-t.x, t.y), depth, tile)
                   + ShadowHardAt(map, uv + vec2(t.x, t.y), depth, tile));
}

// One texel of the receiver's plane, taken off every tap's depth: a tap's bilinear comparison
// reads texels up to one texel from where the plane was evaluated, and the stored depth is
// constant over a texel (the caster's biases cover one comparison at the centre only).
float ShadowPlaneSlack(vec2 slope, vec2 mapSize) { return dot(abs(slope), 1.0 / mapSize); }

// The light's disc over the map: the mean of SHADOW_PCSS_DISC bilinear comparisons on a
// Fibonacci spiral of `radius` texels (tap k at radius √((k + ½)/N), angle k × the golden
// angle: equal areas of the disc), the visibility of a disc light behind a blocker at one
// depth. Numpy twin: app.sim.shadows.disc_taps.
#define SHADOW_PCSS_DISC 32
float ShadowDiscAt(sampler2D map, vec2 uv, float depth, vec4 tile, float radius, vec2 slope) {
    vec2 t = radius / vec2(textureSize(map, 0));
    float slack = ShadowPlaneSlack(slope, vec2(textureSize(map, 0)));
    float sum = 0.0;
    for (int k = 0; k < SHADOW_PCSS_DISC; ++k) {
        float r = sqrt((float(k) + 0.5) / float(SHADOW_PCSS_DISC));
        float a = float(k) * 2.39996323;
        vec2 o = r * vec2(cos(a), sin(a)) * t;
        sum += ShadowBilinearAt(map, uv + o, depth + dot(slope, o) - slack, tile);
    }
    return sum / float(SHADOW_PCSS_DISC);
}

// The receiver's plane in the map (receiver-plane depth bias, Isidoro 2006): d depth / d uv of
// the plane through the point with this normal, so a tap at uv + o compares the receiver's own
// depth there, depth + slope · o, and a wide kernel over a sloped receiver neither shadows it
// nor counts it as a blocker. The slope is capped at that of a plane 85° from facing the light
// (a receiver edge-on to it, which the sun barely lights).
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
    if (abs(det) < 1e-12) return vec2(0.0);
    vec2 slope = vec2(a.z, b.z) * inverse(j);
    // a 45° plane's slope is (depth per metre) / (uv per metre): the matrix's rows' scales
    float perMetreUv = length(vec3(m[0][0], m[1][0], m[2][0]));
    float perMetreDepth = length(vec3(m[0][2], m[1][2], m[2][2]));
    float cap = 11.43 * perMetreDepth / max(perMetreUv, 1e-12);  // tan 85°
    float len = length(slope);
    return len > cap ? slope * (cap / len) : slope;
}

// PCSS: a 7 × 7 blocker search (2-texel steps; fast taps: 4 × 4 in 4-texel steps over the same
// ±6 texels), then the penumbra in texels from the blocker's depth d_b:
// - a perspective map (the spot, a light of finite size; Fernando 2005): d_b the mean blocker,
//   w = pcssScale (d_r − d_b) / d_b, the 5 × 5 Gaussian PCF at that width (0.5..8 texels per
//   tap) whatever the taps (fewer taps spread that far apart band the penumbra);
// - an orthographic one (`parallel`: the sun, at infinity, depths linear in metres): d_b the
//   blocker nearest the receiver (the silhouette that bounds the penumbra: the mean of every
//   blocker in the window includes a convex caster's lit top and widened the spheres' penumbra
//   by 29 % on the surfaces lab's floor), w = pcssScale (d_r − d_b), the light's disc of radius
//   w / 2 (ShadowDiscAt, 0.5..16 texels), every tap against the receiver's plane (`slope`).
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
    float w = pcssScale * (depth - blocker) / (parallel ? 1.0 : max(blocker, 1e-4));
    if (parallel) return ShadowDiscAt(map, uv, depth, tile, clamp(0.5 * w, 0.5, 16.0), slope);
    return ShadowPcfAt(map, uv, depth, tile, clamp(w / float(2 * SHADOW_PCF_RADIUS), 0.5, 8.0),
                       SHADOW_PCF_RADIUS);
}

float ShadowVsm(sampler2D moments, vec2 uv, float depth, vec4 tile, int blur, float bleed) {
    vec2 size = vec2(textureSize(moments, 0));
    vec2 t = 1.0 / size;
    vec2 lo = tile.xy + 0.5 * t, hi = tile.zw - 0.5 * t;
    vec2 m = vec2(0.0);
    float n = 0.0;
    int r = clamp(blur, 0, 4);
    for (int y = -r; y <= r; ++y) {
        for (int x = -r; x <= r; ++x) {
            m += texture(moments, clamp(uv + vec2(x, y) * t, lo, hi)).rg;
            n += 1.0;
        }
    }
    m /= n;
    float d = depth - m.x;
    if (d <= 0.0) return 1.0;
    float variance = max(m.y - m.x * m.x, 1e-6);
    float p = variance / (variance + d * d);
    return clamp((p - bleed) / max(1.0 - bleed, 1e-6), 0.0, 1.0);
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

float ShadowFiltered(sampler2D map, sampler2D moments, vec3 c, vec4 tile, int mode,
                     float pcssScale, int blur, float bleed, int taps, bool parallel,
                     vec2 slope) {
    if (mode == 1) return ShadowFourTap(map, c.xy, c.z, tile);
    if (mode == 2) return ShadowPcfBlock(map, c.xy, c.z, tile, ShadowPcfRadius(taps));
    if (mode == 3) return ShadowPcss(map, c.xy, c.z, tile, pcssScale, taps, parallel, slope);
    if (mode == 4) return ShadowVsm(moments, c.xy, c.z, tile, blur, bleed);
    return ShadowHardAt(map, c.xy, c.z, tile);
}

bool ShadowInside(vec3 c, vec4 tile) {
    return all(greaterThanEqual(c.xy, tile.xy)) && all(lessThanEqual(c.xy, tile.zw))
        && c.z >= 0.0 && c.z <= 1.0;
}

// The sun's cascade of a point at view depth viewDepth (−1 past the shadow distance).
int ShadowCascade(float viewDepth) {
    for (int i = 0; i < 4; ++i) {
        if (i >= uShadowSunCascades) break;
        if (viewDepth <= uShadowSunSplits[i]) return i;
    }
    return -1;
}

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

float ShadowSpot(vec3 worldPos, vec3 worldNormal) {
    if (!uShadowSpotEnabled) return 1.0;
    vec3 offset = worldNormal * uShadowSpotTexelPerM * length(worldPos - uShadowSpotPosition)
                * ShadowFilterReach(SHADOW_SPOT_FILTER, uShadowSpotVsmBlur);
    vec4 h = uShadowSpotMatrix * vec4(worldPos + offset, 1.0);
    if (h.w <= 1e-6) return 1.0;
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

float ShadowPoint(vec3 worldPos, vec3 worldNormal) {
    if (!uShadowPointEnabled || uShadowPointRange <= 0.0) return 1.0;
    int mode = SHADOW_POINT_FILTER;
    float reach = mode == 0 ? 0.0 : (mode == 1 ? 1.0 : 3.0);
    worldPos += worldNormal * reach * uShadowPointTexelPerM * length(worldPos - uShadowPointPosition);
    vec3 l = worldPos - uShadowPointPosition;
    float dist = length(l);
    if (dist < 1e-6 || dist >= uShadowPointRange) return 1.0;
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
