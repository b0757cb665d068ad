#version 330 core
// The surfaces lab's opaque surface (toon-village thesis spec/003 §2.5 reflections, §2.6
// metallic and dielectric, §2.7 refraction and Fresnel, §2.8 shadows), program
// ProgramSpec("surfaces/surface"): surface.vert + this file.
// Equations (tagged where they are implemented): the reflection direction's corrections
// spec/003 eq. 5.1–5.4 (box projection), spec/003 eq. 5.9 (quadratic stretch), spec/003 eq.
// 5.10–5.17 (perfect sphere) in reflection.glsl; the weight spec/003 eq. 5.18 (Table 1) and the
// specular colour lerp there; Snell spec/003 eq. 5.22–5.23, exact Fresnel spec/003 eq. 5.24–5.26
// and Schlick spec/003 eq. 5.27–5.29 in common/fresnel.glsl; the shadow maps in
// common/shadow.glsl.
//
// The colour, as the thesis's shaders sum it:
//   diffuse  = albedo · (ambient + Σ_lights radiance · max(n·l, 0) · visibility · falloff)
//   specular = SpecularIntensityFromLUT(n·h, roughness) · lerp(light colour, albedo, metallic)
//   surface  = lerp(diffuse, probe(ComputeReflexDirection(r)), ReflectionWeight(s, m)) + specular
// or, with surfaces.specular_model = ggx, the split-sum GGX reference: diffuse · (1 − metallic)
// + prefiltered probe · (F0 · A + B). The glass sphere: lerp(refraction, reflection, F) with F
// exact or Schlick, the refracted ray looked up in the probe at the Transparency's mip level.
//
// Interface: vertex inputs in_position, in_normal, in_uv, in_tangent (world space);
// uViewProj, uView, uCameraPos; lights uSunDir/uSunRadiance, uLampOn/uLampPos/uLampRadiance/
// uLampRange, uSpotOn/uSpotPos/uSpotDir/uSpotCos/uSpotRadiance/uSpotRange, uAmbient; material
// uAlbedo, uMetallic, uSmoothness (or uUseMetallicMap with uMetallicMap: R metallic, G
// smoothness), uRefractive, uSphereCentre/uSphereRadius, uN1, uN2,
// uFresnelSchlick, uTransparency, uDistortion, uDistortionMap, uInterfaces; uProbeOn with the
// probe's samplers (reflection.glsl); the shadows' uniforms (common/shadow.glsl); uDebug.
//
// Specialisation: compiled with SURFACE_SCENE defined, the program draws the room and the solids
// seen by the camera — the probe on, no refraction, no debug view, the specular model
// SURFACE_SCENE_SPECULAR (0 or 1) — as constants instead of uProbeOn, uRefractive, uDebug and
// uSpecularModel, so the glass's branch, the other specular model and the debug views are
// compiled out (a software rasteriser runs both sides of a branch on a uniform); with
// common/shadow.glsl's SHADOW_FILTER and SHADOW_TAPS it is one of the twenty variants
// app.effects.surfaces lists. The glass sphere, the probe's own capture and a debug view draw
// with the generic program; the image is the same either way.
//
// Failure cases guarded: normals renormalised with fallbacks; a light exactly behind a face
// or grazing it gives 0, never a negative term; a lamp or spot beyond its range contributes 0
// (the falloff is clamped); total internal reflection in the glass returns the reflected
// direction (RefractDirection's tir flag), so no NaN reaches the probe lookup; the probe's own
// render (uProbeOn false) reads no probe, so the cubemap never samples itself.
#include "math.glsl"
#include "shadow.glsl"
#include "fresnel.glsl"
#include "reflection.glsl"
#include "refraction.glsl"

in vec3 vWorldPos;
in vec3 vWorldNormal;
in vec4 vWorldTangent;
in vec2 vUV;
in float vViewDepth;
in vec3 vReflect;

uniform vec3 uCameraPos;
uniform vec3 uSunDir;
uniform vec3 uSunRadiance;
uniform vec3 uAmbient;
uniform bool uLampOn;
uniform vec3 uLampPos;
uniform vec3 uLampRadiance;
uniform float uLampRange;
uniform bool uSpotOn;
uniform vec3 uSpotPos;
uniform vec3 uSpotDir;
uniform vec2 uSpotCos;
uniform vec3 uSpotRadiance;
uniform float uSpotRange;

uniform vec3 uAlbedo;
uniform float uMetallic;
uniform float uSmoothness;
uniform bool uUseMetallicMap;      // the object's R = metallic, G = smoothness texture (spec/003 §2.6)
uniform sampler2D uMetallicMap;
float gMetallic, gSmoothness;      // this fragment's: the sliders', or the texture's
uniform bool uRefractive;
uniform vec3 uSphereCentre;
uniform float uSphereRadius;
uniform float uN1;
uniform float uN2;
uniform bool uFresnelSchlick;
uniform float uTransparency;
uniform float uDistortion;
uniform sampler2D uDistortionMap;
uniform int uInterfaces;
uniform bool uProbeOn;
uniform int uDebug;
uniform bool uReflectionOptimize;  // its parameter annotation is in surface.vert

// the probe (app.effects.surfaces.reflections.ReflectionProbe.bind)
uniform samplerCube uProbe;            // the room seen from the probe, with mips
uniform samplerCube uProbePrefiltered; // GGX-prefiltered copy, one mip per roughness
uniform sampler2D uBrdfLut;            // the split sum's (A, B)
uniform sampler2D uNhxLut;             // Unity's NHxRoughness, recreated
uniform vec3 uProbePos;
uniform vec3 uProbeBoxMin;
uniform vec3 uProbeBoxMax;
uniform float uProbeSphereRadius;
uniform float uProbeMips;
uniform float uPrefilteredMips;
uniform int uReflection;       // surfaces.reflection: 0 none, 1 cube, 2 box, 3 approximation, 4 perfect
uniform int uSpecularModel;    // surfaces.specular_model: 0 the thesis's, 1 split-sum GGX

out vec4 fragColor;

#ifdef SURFACE_SCENE
#define PROBE_ON true
#define REFRACTIVE false
#define DEBUG_VIEW 0
#define SPECULAR_MODEL SURFACE_SCENE_SPECULAR
#else
#define PROBE_ON uProbeOn
#define REFRACTIVE uRefractive
#define DEBUG_VIEW uDebug
#define SPECULAR_MODEL uSpecularModel
#endif

// Unity's distance falloff of a point light within its range: (1 − (d/range)²)², 0 beyond.
float RangeFalloff(float d, float range) {
    float x = clamp(d / max(range, 1e-4), 0.0, 1.0);
    float f = 1.0 - x * x;
    return f * f;
}

// One light's diffuse and specular (the thesis's LUT specular, spec/003 §2.6).
void AddLight(vec3 l, vec3 radiance, vec3 n, vec3 v, float roughness, inout vec3 diffuse,
              inout vec3 specular) {
    float nl = max(dot(n, l), 0.0);
    if (nl <= 0.0) return;
    diffuse += radiance * nl;
    vec3 h = SafeNormalize(l + v, n);
    float nh = max(dot(n, h), 0.0);
    float spec = SPECULAR_MODEL == 0 ? SpecularIntensityFromLUT(uNhxLut, nh, roughness) : 0.0;
    specular += spec * nl * SpecularColorByMetallic(radiance, uAlbedo, gMetallic);
}

void main() {
    gMetallic = uMetallic;
    gSmoothness = uSmoothness;
    if (uUseMetallicMap) {
        vec2 ms = texture(uMetallicMap, vUV).rg;
        gMetallic = ms.r;
        gSmoothness = ms.g;
    }
    vec3 v = SafeNormalize(uCameraPos - vWorldPos, vec3(0.0, 0.0, 1.0));
    vec3 n = SafeNormalize(vWorldNormal, v);
    if (REFRACTIVE && uDistortion > 0.0) {
        vec3 t = SafeNormalize(vWorldTangent.xyz, vec3(1.0, 0.0, 0.0));
        vec3 b = cross(n, t) * (vWorldTangent.w < 0.0 ? -1.0 : 1.0);
        vec2 xy = texture(uDistortionMap, vUV * 4.0).xy * 2.0 - 1.0;
        n = DistortNormal(n, t, b, xy, DistortionStrength(uDistortion, gSmoothness));
    }
    float roughness = 1.0 - gSmoothness;

    // the lights, each with its shadow map (spec/003 §2.8)
    vec3 diffuse = uAmbient;
    vec3 specular = vec3(0.0);
    float sunVis = ShadowSun(vWorldPos, n, vViewDepth);
    AddLight(SafeNormalize(uSunDir, vec3(0.0, 1.0, 0.0)), uSunRadiance * sunVis, n, v, roughness,
             diffuse, specular);
    if (uLampOn) {
        vec3 toLamp = uLampPos - vWorldPos;
        float d = length(toLamp);
        float vis = ShadowPoint(vWorldPos, n);
        AddLight(toLamp / max(d, 1e-4), uLampRadiance * RangeFalloff(d, uLampRange) * vis, n, v,
                 roughness, diffuse, specular);
    }
    if (uSpotOn) {
        vec3 toSpot = uSpotPos - vWorldPos;
        float d = length(toSpot);
        vec3 l = toSpot / max(d, 1e-4);
        float cone = smoothstep(uSpotCos.y, max(uSpotCos.x, uSpotCos.y + 1e-4), dot(-l, uSpotDir));
        float vis = ShadowSpot(vWorldPos, n);
        AddLight(l, uSpotRadiance * cone * RangeFalloff(d, uSpotRange) * vis, n, v, roughness,
                 diffuse, specular);
    }
    diffuse *= uAlbedo;

    vec3 colour = diffuse + specular;
    vec3 r = reflect(-v, n);
    if (uReflectionOptimize && dot(vReflect, vReflect) > 1e-12 && uDistortion <= 0.0) {
        r = normalize(vReflect);  // REFLECTION_OPTIMIZE: interpolated from the vertices
    }
    // the probe's lookup direction of r, once: the reflection, the GGX reference and the debug
    // view share it (reflection none looks the glass's reflection up as cube)
    vec3 dR = ComputeReflexDirection(max(uReflection, 1), vWorldPos, r, uProbePos, uProbeBoxMin,
                                     uProbeBoxMax, uProbeSphereRadius);
    if (PROBE_ON && REFRACTIVE) {
        // the glass: refraction against reflection, weighted by the reflectance (spec/003 §2.7)
        float cosI = clamp(dot(n, v), 0.0, 1.0);
        float F = uFresnelSchlick ? FresnelSchlick(cosI, uN1, uN2) : FresnelExact(cosI, uN1, uN2);
        bool tir;
        vec3 t;
        if (uDistortion > 0.0) {
            t = RefractDirection(-v, n, uN1 / uN2, tir);  // the distorted normal, one interface
        } else {
            t = RefractSphere(uInterfaces, vWorldPos, -v, uSphereCentre, uSphereRadius, uN1 / uN2, tir);
        }
        vec3 d = ComputeReflexDirection(uReflection == 0 ? 1 : uReflection, vWorldPos, t,
                                        uProbePos, uProbeBoxMin, uProbeBoxMax, uProbeSphereRadius);
        vec3 refracted = textureLod(uProbe, d, RefractionLod(uTransparency, uProbeMips)).rgb * uAlbedo;
        vec3 reflected = SampleProbe(uProbe, dR, gSmoothness, uProbeMips);
        colour = RefractReflectMix(refracted, reflected, F) + specular;
    } else if (PROBE_ON && uReflection != 0) {
        if (SPECULAR_MODEL == 1) {
            // the physically based reference: split-sum prefiltered GGX (Karis 2013)
            vec3 f0 = mix(vec3(0.04), uAlbedo, gMetallic);
            vec3 spec = PrefilteredSpecular(uProbePrefiltered, uBrdfLut, dR, max(dot(n, v), 0.0),
                                            roughness, f0, uPrefilteredMips);
            colour = diffuse * (1.0 - gMetallic) + spec;
        } else {
            float w = ReflectionWeight(gSmoothness, gMetallic);
            colour = mix(diffuse, SampleProbe(uProbe, dR, gSmoothness, uProbeMips), w) + specular;
        }
    }

    if (DEBUG_VIEW == 1) {
        int c = ShadowCascade(vViewDepth);
        colour = vec3(c == 0 ? 1.0 : 0.2, c == 1 ? 1.0 : 0.2, c >= 2 ? 1.0 : 0.2) * (c == 3 ? 0.6 : 1.0)
                 * (0.4 + 0.6 * sunVis);
    } else if (DEBUG_VIEW == 2) {
        colour = vec3(sunVis);
    } else if (DEBUG_VIEW == 3) {
        colour = 0.5 + 0.5 * dR;
    }
    fragColor = vec4(colour, 1.0);
}
