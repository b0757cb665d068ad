#version 330 core
// GPU probe of glsl/surfaces/reflection.glsl (spec/003 §2.5, §2.6) for the tests and the
// bench: the functions evaluated at the points of uPoints (one per pixel) so they can be
// compared with the numpy twin app/sim/reflections.py.
//   uEvalMode 0: p = world position, uDir the reflected direction (or, with uPerPointDir,
//                p − uEye reflected about uNormal): (ComputeReflexDirection(uReflection, …), t)
//                where t is SphereSegmentT for the perfect sphere's segment
//             1: p = (smoothness, metallic, nh): (ReflectionWeight, SpecularIntensityFromLUT
//                at roughness 1 − smoothness, SpecularColorByMetallic(uLight, uAlbedo, m).rg)
//             2: p = world position on a mirror: the probe colour seen along the corrected
//                reflection of the ray from uEye (normal uNormal, or the sphere's at
//                uSphereCentre when uSphereNormal), SampleProbe at uSmoothness
//             3: p = direction: SampleProbe(uProbe, p, uSmoothness) (mode 4 with uGgx:
//                PrefilteredSpecular at roughness 1 − uSmoothness, F0 1)
//             5: p = point on the sphere at uSphereCentre seen from uEye: the thesis's colour
//                (uGgx 0) or the split-sum GGX reference (uGgx 1) of the metallic/dielectric
//                material (uAlbedo, uSmoothness, uMetallic) lit by the probe alone
// Failure cases guarded: as reflection.glsl; the points texture is read with texelFetch.
#include "reflection.glsl"

uniform sampler2D uPoints;
uniform samplerCube uProbe;
uniform samplerCube uProbePrefiltered;
uniform sampler2D uBrdfLut;
uniform sampler2D uNhxLut;
uniform vec3 uProbePos;
uniform vec3 uProbeBoxMin;
uniform vec3 uProbeBoxMax;
uniform float uProbeSphereRadius;
uniform float uProbeMips;
uniform float uPrefilteredMips;
uniform int uEvalMode;
uniform int uReflection;
uniform vec3 uDir;
uniform vec3 uEye;
uniform vec3 uNormal;
uniform vec3 uSphereCentre;
uniform int uSphereNormal;
uniform int uPerPointDir;
uniform float uSmoothness;
uniform float uMetallic;
uniform vec3 uAlbedo;
uniform vec3 uLight;
uniform int uGgx;

out vec4 fragColor;

vec3 mirrorNormal(vec3 p) {
    return uSphereNormal == 1 ? normalize(p - uSphereCentre) : normalize(uNormal);
}

void main() {
    vec3 p = texelFetch(uPoints, ivec2(gl_FragCoord.xy), 0).xyz;
    if (uEvalMode == 0) {
        vec3 dir = uPerPointDir == 1 ? reflect(normalize(p - uEye), mirrorNormal(p))
                                     : normalize(uDir);
        float len = 2.0 * uProbeSphereRadius + length(p - uProbePos);
        float t = SphereSegmentT(p, p + len * dir, uProbePos, uProbeSphereRadius);
        fragColor = vec4(ComputeReflexDirection(uReflection, p, dir, uProbePos, uProbeBoxMin,
                                                uProbeBoxMax, uProbeSphereRadius), t);
    } else if (uEvalMode == 1) {
        fragColor = vec4(ReflectionWeight(p.x, p.y),
                         SpecularIntensityFromLUT(uNhxLut, p.z, 1.0 - p.x),
                         SpecularColorByMetallic(uLight, uAlbedo, p.y).rg);
    } else if (uEvalMode == 2) {
        vec3 dir = reflect(normalize(p - uEye), mirrorNormal(p));
        vec3 look = ComputeReflexDirection(uReflection, p, dir, uProbePos, uProbeBoxMin,
                                           uProbeBoxMax, uProbeSphereRadius);
        fragColor = vec4(SampleProbe(uProbe, look, uSmoothness, uProbeMips), 1.0);
    } else if (uEvalMode == 3) {
        fragColor = vec4(SampleProbe(uProbe, normalize(p), uSmoothness, uProbeMips), 1.0);
    } else if (uEvalMode == 4) {
        fragColor = vec4(PrefilteredSpecular(uProbePrefiltered, uBrdfLut, normalize(p), 1.0,
                                             1.0 - uSmoothness, vec3(1.0), uPrefilteredMips),
                         1.0);
    } else {
        vec3 n = normalize(p - uSphereCentre);
        vec3 v = normalize(uEye - p);
        float nv = max(dot(n, v), 0.0);
        vec3 r = reflect(-v, n);
        vec3 look = ComputeReflexDirection(uReflection, p, r, uProbePos, uProbeBoxMin,
                                           uProbeBoxMax, uProbeSphereRadius);
        // irradiance stand-in shared by both models: the roughest prefiltered level along n
        vec3 irradiance = textureLod(uProbePrefiltered, n, uPrefilteredMips - 1.0).rgb;
        vec3 diffuse = uAlbedo * irradiance;
        vec3 colour;
        if (uGgx == 0) {
            float w = ReflectionWeight(uSmoothness, uMetallic);
            vec3 tint = SpecularColorByMetallic(vec3(1.0), uAlbedo, uMetallic);
            colour = mix(diffuse, SampleProbe(uProbe, look, uSmoothness, uProbeMips) * tint, w);
        } else {
            vec3 f0 = mix(vec3(0.04), uAlbedo, uMetallic);
            float rough = 1.0 - uSmoothness;
            vec3 spec = PrefilteredSpecular(uProbePrefiltered, uBrdfLut, look, nv, rough, f0,
                                            uPrefilteredMips);
            float fr = 0.04 + 0.96 * pow(1.0 - nv, 5.0);
            colour = diffuse * (1.0 - uMetallic) * (1.0 - fr) + spec;
        }
        fragColor = vec4(colour, 1.0);
    }
}
