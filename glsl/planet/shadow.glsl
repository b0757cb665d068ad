// =============================================================================================
// Sun visibility from the static orthographic shadow map (spec/002 §3.1–3.2): rendered from the
// sun only when the light direction changes; V(P) = 0 where P is deeper than the stored depth.
// Filtering (§3.2, "processing the map"): a Gaussian-weighted neighbourhood (5×5, σ = 1 texel)
// of bilinear depth comparisons — the variant the thesis kept — or a single nearest comparison.
// Points outside the map's box are lit. A slope-scaled bias avoids self-shadowing acne.
// =============================================================================================
uniform sampler2D uShadowMap;   // depth in [0, 1], orthographic from the sun
uniform mat4 uLightViewProj;    // local frame → light clip space
uniform bool uShadowFiltered;   // Gaussian + bilinear (true) or nearest, unfiltered (false)
uniform float uShadowBias;      // in depth units
uniform bool uShadowsEnabled;

float ShadowCompareBilinear(vec2 uv, float depth) {
    vec2 size = vec2(textureSize(uShadowMap, 0));
    vec2 st = uv * size - 0.5;
    vec2 f = fract(st);
    ivec2 i = ivec2(floor(st));
    ivec2 hi = ivec2(size) - 1;
    float s00 = step(depth, texelFetch(uShadowMap, clamp(i, ivec2(0), hi), 0).r);
    float s10 = step(depth, texelFetch(uShadowMap, clamp(i + ivec2(1, 0), ivec2(0), hi), 0).r);
    float s01 = step(depth, texelFetch(uShadowMap, clamp(i + ivec2(0, 1), ivec2(0), hi), 0).r);
    float s11 = step(depth, texelFetch(uShadowMap, clamp(i + ivec2(1, 1), ivec2(0), hi), 0).r);
    return mix(mix(s00, s10, f.x), mix(s01, s11, f.x), f.y);
}

// 1 = lit, 0 = in shadow; local = position in the local frame.
float ShadowVisibility(vec3 local, float bias) {
    if (!uShadowsEnabled) return 1.0;
    vec4 clip = uLightViewProj * vec4(local, 1.0);
    vec3 p = clip.xyz / clip.w * 0.5 + 0.5;
    if (any(lessThan(p, vec3(0.0))) || any(greaterThan(p, vec3(1.0)))) return 1.0;
    float depth = p.z - bias;
    if (!uShadowFiltered) {
        ivec2 texel = ivec2(p.xy * vec2(textureSize(uShadowMap, 0)));
        return step(depth, texelFetch(uShadowMap, texel, 0).r);
    }
    vec2 texelSize = 1.0 / vec2(textureSize(uShadowMap, 0));
    float sum = 0.0, wsum = 0.0;
    for (int y = -2; y <= 2; ++y) {
        for (int x = -2; x <= 2; ++x) {
            float w = exp(-0.5 * float(x * x + y * y));
            sum += w * ShadowCompareBilinear(p.xy + vec2(x, y) * texelSize, depth);
            wsum += w;
        }
    }
    return sum / wsum;
}

// Cheap point visibility for the in-scattering integral's V(P) (light shafts): one bilinear
// comparison per sample.
float ShadowVisibilityPoint(vec3 local) {
    if (!uShadowsEnabled) return 1.0;
    vec4 clip = uLightViewProj * vec4(local, 1.0);
    vec3 p = clip.xyz / clip.w * 0.5 + 0.5;
    if (any(lessThan(p, vec3(0.0))) || any(greaterThan(p, vec3(1.0)))) return 1.0;
    return ShadowCompareBilinear(p.xy, p.z - uShadowBias);
}
