#version 330 core
// The surfaces lab's opaque surface (toon-village thesis spec/003 §2.5 reflections, §2.6
// metallic and dielectric, §2.7 refraction and Fresnel, §2.8 shadows), program
// ProgramSpec("surfaces/surface"): surface.vert + this file. Linear radiance of the room, the
// solids and the glass sphere lit by a sun, a lamp and a spot, each with its shadow map, and
// reflecting the room's probe. Equations are tagged where they are implemented:
// reflection.glsl (probe corrections, weight, specular colour), refraction.glsl and
// common/fresnel.glsl (Snell, Fresnel), common/shadow.glsl. Compiled with SURFACE_SCENE, it is
// one of the twenty specialised variants app.effects.surfaces lists (see the #ifdef below).
// Failure cases guarded: normals renormalised with fallbacks; a light behind or grazing a face
// gives 0; a light beyond its range gives 0; total internal reflection in the glass never sends
// a NaN to the probe; the probe's own render reads no probe (no cubemap samples itself).
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

// Camera and lights (world space, metres; radiance linear): the sun, a point lamp and a spot
// (uSpotCos: cosines of the cone's inner and outer edges).
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

// The material: albedo (linear), metallic and smoothness (or their texture), and the glass
// sphere's refraction (indices uN1 outside, uN2 inside; refraction.glsl).
uniform vec3 uAlbedo;
uniform float uMetallic;
uniform float uSmoothness;
uniform bool uUseMetallicMap;  // the object's R = metallic, G = smoothness texture (spec/003 §2.6)
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
uniform int uReflection;     // surfaces.reflection: 0 none, 1 cube, 2 box, 3 approx., 4 perfect
uniform int uSpecularModel;  // surfaces.specular_model: 0 the thesis's, 1 split-sum GGX

out vec4 fragColor;

//: m: the smallest light range and light distance divided by
const float MIN_LIGHT_DISTANCE = 1e-4;
//: the smallest width of the spot's soft edge, in cosine
const float MIN_SPOT_EDGE = 1e-4;
//: repeats of the distortion map across the object's UVs
const float DISTORTION_TILING = 4.0;
//: squared length under which the vertices' reflected direction is taken as missing
const float MIN_REFLECT2 = 1e-12;
//: the split-sum reference's F0 of a dielectric (the common 4 %)
const float DIELECTRIC_F0 = 0.04;
//: debug view 1: the cascades' colours (a channel lit 1.0 or dim), cascade 3 darkened, and the
//: sun's visibility shading them from DEBUG_SHADE_FLOOR up
const float DEBUG_DIM = 0.2;
const float DEBUG_CASCADE3 = 0.6;
const float DEBUG_SHADE_FLOOR = 0.4;
const float DEBUG_SHADE_SPAN = 0.6;

// Specialisation: compiled with SURFACE_SCENE defined, the program draws the room and the
// solids seen by the camera — the probe on, no refraction, no debug view, the specular model
// SURFACE_SCENE_SPECULAR (0 or 1) — as constants instead of uProbeOn, uRefractive, uDebug and
// uSpecularModel, so the glass's branch, the other specular model and the debug views are
// compiled out (a software rasteriser runs both sides of a branch on a uniform); with
// common/shadow.glsl's SHADOW_FILTER and SHADOW_TAPS it is one of the twenty variants
// app.effects.surfaces lists. The glass sphere, the probe's own capture and a debug view draw
// with the generic program; the image is the same either way.
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
// d and range in metres; result in [0, 1]. A zero range is raised to MIN_LIGHT_DISTANCE.
float RangeFalloff(float d, float range) {
    float x = clamp(d / max(range, MIN_LIGHT_DISTANCE), 0.0, 1.0);
    float f = 1.0 - x * x;
    return f * f;
}

// One light's diffuse and specular (the thesis's LUT specular, spec/003 §2.6), added to the
// sums: l the unit direction toward the light, radiance linear (already shadowed and faded),
// n and v unit. A light behind or grazing the face adds nothing; l + v = 0 falls back to n.
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

// The colour, as the thesis's shaders sum it:
//   diffuse  = albedo · (ambient + Σ_lights radiance · max(n·l, 0) · visibility · falloff)
//   specular = SpecularIntensityFromLUT(n·h, roughness) · lerp(light colour, albedo, metallic)
//   surface  = lerp(diffuse, probe(ComputeReflexDirection(r)), ReflectionWeight(s, m))
//              + specular
// or, with surfaces.specular_model = ggx, the split-sum GGX reference: diffuse · (1 − metallic)
// + prefiltered probe · (F0 · A + B). The glass sphere: lerp(refraction, reflection, F) with F
// exact or Schlick, the refracted ray looked up in the probe at the Transparency's mip level.
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
        vec2 xy = texture(uDistortionMap, vUV * DISTORTION_TILING).xy * 2.0 - 1.0;
        n = DistortNormal(n, t, b, xy, DistortionStrength(uDistortion, gSmoothness));
    }
    float roughness = 1.0 - gSmoothness;

    // the lights, each with its shadow map (spec/003 §2.8)
    vec3 diffuse = uAmbient;
    vec3 specular = vec3(0.0);
    float sunVis = ShadowSun(vWorldPos, n, vViewDepth);
    AddLight(SafeNormalize(uSunDir, vec3(0.0, 1.0, 0.0)), uSunRadiance * sunVis, n, v,
             roughness, diffuse, specular);
    if (uLampOn) {
        vec3 toLamp = uLampPos - vWorldPos;
        float d = length(toLamp);
        float vis = ShadowPoint(vWorldPos, n);
        AddLight(toLamp / max(d, MIN_LIGHT_DISTANCE),
                 uLampRadiance * RangeFalloff(d, uLampRange) * vis, n, v, roughness, diffuse,
                 specular);
    }
    if (uSpotOn) {
        vec3 toSpot = uSpotPos - vWorldPos;
        float d = length(toSpot);
        vec3 l = toSpot / max(d, MIN_LIGHT_DISTANCE);
        float inner = max(uSpotCos.x, uSpotCos.y + MIN_SPOT_EDGE);
        float cone = smoothstep(uSpotCos.y, inner, dot(-l, uSpotDir));
        float vis = ShadowSpot(vWorldPos, n);
        AddLight(l, uSpotRadiance * cone * RangeFalloff(d, uSpotRange) * vis, n, v, roughness,
                 diffuse, specular);
    }
    diffuse *= uAlbedo;

    vec3 colour = diffuse + specular;
    vec3 r = reflect(-v, n);
    if (uReflectionOptimize && dot(vReflect, vReflect) > MIN_REFLECT2 && uDistortion <= 0.0) {
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
            t = RefractSphere(uInterfaces, vWorldPos, -v, uSphereCentre, uSphereRadius,
                              uN1 / uN2, tir);
        }
        vec3 d = ComputeReflexDirection(uReflection == 0 ? 1 : uReflection, vWorldPos, t,
                                        uProbePos, uProbeBoxMin, uProbeBoxMax, uProbeSphereRadius);
        vec3 refracted = textureLod(uProbe, d, RefractionLod(uTransparency, uProbeMips)).rgb
                       * uAlbedo;
        vec3 reflected = SampleProbe(uProbe, dR, gSmoothness, uProbeMips);
        colour = RefractReflectMix(refracted, reflected, F) + specular;
    } else if (PROBE_ON && uReflection != 0) {
        if (SPECULAR_MODEL == 1) {
            // the physically based reference: split-sum prefiltered GGX (Karis 2013)
            vec3 f0 = mix(vec3(DIELECTRIC_F0), uAlbedo, gMetallic);
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
        colour = vec3(c == 0 ? 1.0 : DEBUG_DIM, c == 1 ? 1.0 : DEBUG_DIM,
                      c >= 2 ? 1.0 : DEBUG_DIM) * (c == 3 ? DEBUG_CASCADE3 : 1.0)
                 * (DEBUG_SHADE_FLOOR + DEBUG_SHADE_SPAN * sunVis);
    } else if (DEBUG_VIEW == 2) {
        colour = vec3(sunVis);
    } else if (DEBUG_VIEW == 3) {
        colour = 0.5 + 0.5 * dR;
    }
    fragColor = vec4(colour, 1.0);
}
