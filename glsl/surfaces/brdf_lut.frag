#version 330 core
// The split-sum BRDF LUT (Karis 2013, second sum) for the surfaces lab's GGX reference
// (spec/003 §2.6): texel (n·v = vUV.x, perceptual roughness = vUV.y) holds (A, B) with
// ∫ f·cos = F0·A + B for the GGX BRDF with Smith–Schlick visibility (k = α/2), α = roughness².
// Numpy twin: app.sim.reflections.brdf_lut (the same Hammersley points).
// Failure cases guarded: n·v is kept ≥ 1e-3 (no division by 0 at grazing view); samples with
// n·l ≤ 0 add nothing; roughness is kept ≥ 1e-3 so the GGX lobe is never a delta.
#include "reflection.glsl"

in vec2 vUV;
out vec4 fragColor;

uniform int uSamples;

void main() {
    float nv = max(vUV.x, 1e-3);
    float alpha = max(vUV.y, 1e-3);
    alpha *= alpha;
    vec3 v = vec3(sqrt(1.0 - nv * nv), 0.0, nv);
    vec3 n = vec3(0.0, 0.0, 1.0);
    float a = 0.0, b = 0.0;
    uint count = uint(max(uSamples, 1));
    for (uint i = 0u; i < count; ++i) {
        vec3 h = ImportanceSampleGGX(Hammersley(i, count), n, alpha);
        vec3 l = 2.0 * dot(v, h) * h - v;
        float nl = l.z;
        if (nl <= 0.0) continue;
        float nh = max(h.z, 0.0);
        float vh = max(dot(v, h), 0.0);
        float gVis = SmithGIbl(nv, nl, alpha) * vh / max(nh * nv, 1e-6);
        float fc = pow(1.0 - vh, 5.0);
        a += (1.0 - fc) * gVis;
        b += fc * gVis;
    }
    fragColor = vec4(a / float(count), b / float(count), 0.0, 1.0);
}
