// =============================================================================================
// Percentage-closer filtering of a depth shadow map — the shared filter of every shadowed
// receiver (atmospheric-scattering thesis spec/002 §3.2, "processing the map"): a Gaussian-
// weighted neighbourhood of (2 r + 1)² bilinear depth comparisons, r = SHADOW_PCF_RADIUS texels
// (2: a 5×5 kernel; the thesis gives no size), σ = SHADOW_PCF_SIGMA texels (1), weights
// w = exp(−(x² + y²) / (2 σ²)).
// Numpy twin: app/render/shadows.py (pcf_weights, compare_bilinear, pcf_visibility; the same
// radius and σ, PCF_RADIUS and PCF_SIGMA), which the planet's shadow tests read the map with.
//
// One bilinear comparison is the hardware's: a sampler2DShadow on a depth texture with the
// compare mode on ('<=') and LINEAR filtering returns the bilinear blend of the four texels'
// (depth ≤ stored) results in one read (set up by app.render.shadows.configure_compare). The
// manual twin of it — four texelFetch and a blend — is kept for a sampler2D (the compare mode
// off): the same result within float rounding (the bench's "changes" section measures it), at
// four times the reads. Both overloads take the same arguments, so a receiver switches with the
// type of its sampler uniform alone.
//
// Bias: ShadowSlopeBias grows the constant bias with 1 − N·L (faces turned from the light need
// more); the receiver subtracts it from its light-space depth before comparing.
//
// Failure cases guarded: texels outside the map clamp to its edge (clamp-to-edge for the
// hardware read, clamped indices for the manual one), so the filter never wraps around; a
// reference depth below 0 (a large bias) is lit in both (the hardware clamps it to 0, which
// every stored depth passes; step() passes it too); the Gaussian's weights are normalised by
// their sum, so a changed radius or σ keeps V in [0, 1].
// =============================================================================================
#ifndef SHADOW_PCF_RADIUS
#define SHADOW_PCF_RADIUS 2
#endif
#ifndef SHADOW_PCF_SIGMA
#define SHADOW_PCF_SIGMA 1.0
#endif

// The slope-scaled bias: bias · (1 + 4 (1 − N·L)).
float ShadowSlopeBias(float bias, float nDotL) { return bias * (1.0 + 4.0 * (1.0 - nDotL)); }

// One bilinear comparison, in hardware: 1 = lit.
float ShadowCompareBilinear(sampler2DShadow map, vec2 uv, float depth) {
    return texture(map, vec3(uv, depth));
}

// One bilinear comparison by hand (the compare mode off): four texels, four steps, a blend.
float ShadowCompareBilinear(sampler2D map, vec2 uv, float depth) {
    vec2 size = vec2(textureSize(map, 0));
    vec2 st = uv * size - 0.5;
    vec2 f = fract(st);
    ivec2 i = ivec2(floor(st));
    ivec2 hi = ivec2(size) - 1;
    float s00 = step(depth, texelFetch(map, clamp(i, ivec2(0), hi), 0).r);
    float s10 = step(depth, texelFetch(map, clamp(i + ivec2(1, 0), ivec2(0), hi), 0).r);
    float s01 = step(depth, texelFetch(map, clamp(i + ivec2(0, 1), ivec2(0), hi), 0).r);
    float s11 = step(depth, texelFetch(map, clamp(i + ivec2(1, 1), ivec2(0), hi), 0).r);
    return mix(mix(s00, s10, f.x), mix(s01, s11, f.x), f.y);
}

// The nearest texel's comparison, unfiltered (a hard edge): the texel's centre read through the
// bilinear hardware compare has weights (1, 0), so it is that texel's result.
float ShadowCompareNearest(sampler2DShadow map, vec2 uv, float depth) {
    vec2 size = vec2(textureSize(map, 0));
    return texture(map, vec3((floor(uv * size) + 0.5) / size, depth));
}

float ShadowCompareNearest(sampler2D map, vec2 uv, float depth) {
    ivec2 texel = ivec2(uv * vec2(textureSize(map, 0)));
    return step(depth, texelFetch(map, texel, 0).r);
}

// The Gaussian-weighted (2 r + 1)² neighbourhood of bilinear comparisons about uv: 1 = lit
// (spelled out for each sampler type: GLSL 3.30 has no generic functions).
float ShadowPcfWeight(int x, int y) {
    return exp(-0.5 * float(x * x + y * y) / (SHADOW_PCF_SIGMA * SHADOW_PCF_SIGMA));
}

// The PCF with the hardware's bilinear comparison (a compare-mode depth texture), in [0, 1]:
// the weights are normalised by their sum.
float ShadowPcf(sampler2DShadow map, vec2 uv, float depth) {
    vec2 texelSize = 1.0 / vec2(textureSize(map, 0));
    float sum = 0.0, wsum = 0.0;
    for (int y = -SHADOW_PCF_RADIUS; y <= SHADOW_PCF_RADIUS; ++y) {
        for (int x = -SHADOW_PCF_RADIUS; x <= SHADOW_PCF_RADIUS; ++x) {
            float w = ShadowPcfWeight(x, y);
            sum += w * ShadowCompareBilinear(map, uv + vec2(x, y) * texelSize, depth);
            wsum += w;
        }
    }
    return sum / wsum;
}

// The same PCF on a plain sampler2D (the compare mode off), the manual bilinear comparison
// of four texelFetch per tap.
float ShadowPcf(sampler2D map, vec2 uv, float depth) {
    vec2 texelSize = 1.0 / vec2(textureSize(map, 0));
    float sum = 0.0, wsum = 0.0;
    for (int y = -SHADOW_PCF_RADIUS; y <= SHADOW_PCF_RADIUS; ++y) {
        for (int x = -SHADOW_PCF_RADIUS; x <= SHADOW_PCF_RADIUS; ++x) {
            float w = ShadowPcfWeight(x, y);
            sum += w * ShadowCompareBilinear(map, uv + vec2(x, y) * texelSize, depth);
            wsum += w;
        }
    }
    return sum / wsum;
}
