#version 330 core
// GGX-prefiltered environment (Karis 2013, split-sum, first sum) for the surfaces lab's
// reflection probe (spec/003 §2.5): one face of one mip level of the prefiltered cube, the
// level's perceptual roughness uRoughness (α = roughness²), n = v = r assumed. Each texel sums
// uSamples GGX-importance-sampled light directions weighted by n·l, each read from the source
// cube at the mip level matching its sample's solid angle (filtered importance sampling,
// Colbert and Krivanek 2007), so 64 samples stay free of fireflies.
// Failure cases guarded: roughness 0 reads the source texel directly (the GGX lobe is a
// delta); samples with n·l ≤ 0 add nothing, and a sum of weights of 0 falls back to the
// direct read; the pdf is clamped away from 0 before its logarithm.
#include "../common/cubemap.glsl"
#include "reflection.glsl"

in vec2 vUV;
out vec4 fragColor;

uniform samplerCube uSource;
uniform int uFace;
uniform float uRoughness;
uniform int uSamples;
uniform float uSourceSize;  // face size of the source's level 0
uniform float uSourceMips;  // mip levels of the source

void main() {
    vec3 n = CubemapFaceDirection(uFace, vUV * 2.0 - 1.0);
    if (uRoughness <= 0.0) {
        fragColor = vec4(textureLod(uSource, n, 0.0).rgb, 1.0);
        return;
    }
    float alpha = uRoughness * uRoughness;
    float texelSolid = 4.0 * PI / (6.0 * uSourceSize * uSourceSize);
    vec3 sum = vec3(0.0);
    float weight = 0.0;
    uint count = uint(max(uSamples, 1));
    for (uint i = 0u; i < count; ++i) {
        vec3 h = ImportanceSampleGGX(Hammersley(i, count), n, alpha);
        vec3 l = 2.0 * dot(n, h) * h - n;
        float nl = dot(n, l);
        if (nl <= 0.0) continue;
        float nh = max(dot(n, h), 0.0);
        float pdf = max(GgxD(nh, alpha) * 0.25, 1e-6);  // n = v: D·(n·h)/(4 v·h) = D/4
        float sampleSolid = 1.0 / (float(count) * pdf);
        float lod = clamp(0.5 * log2(sampleSolid / texelSolid) + 1.0, 0.0, uSourceMips - 1.0);
        sum += textureLod(uSource, l, lod).rgb * nl;
        weight += nl;
    }
    fragColor = vec4(weight > 0.0 ? sum / weight : textureLod(uSource, n, 0.0).rgb, 1.0);
}
