#version 330 core
// The toon village's water (spec/003 §2.10, the thesis's §7.2 Custom/Nature/Water), one pass
// lit by the main directional light only, program ProgramSpec("toon_water/water_simple" |
// "water_complex" | "water_complex_pow5") — water.vert + this file with WATER_COMPLEX (the
// repository's multi_compile WATER_SIMPLE WATER_COMPLEX) and WATER_FRESNEL_RAMP:
//   refraction  the grab of the image drawn so far (uGrab), sampled at the fragment's screen
//               coordinates distorted by the one normal map sampled twice (WaveUVs,
//               WaveNormal, RefractionOffset: spec/003 eq. 3.1, spec/003 eq. 3.4), under the
//               depth fog (uDepthFog, uFogMethod: document, repository, thickness) and mixed
//               with the lit water colour (WaterRefraction)
//   Simple      refraction + Band Strength·SimpleBand(n·v)·light: v·n in 3 bands
//               (spec/003 eq. 7.18, spec/003 eq. 7.19, spec/003 eq. 7.20)
//   Complex     lerp(refraction, reflection, F): the probe cubemap's reflection discretised with
//               Toon Value (spec/003 eq. 7.18, spec/003 eq. 7.19, spec/003 eq. 7.20), optionally
//               20 % toward the water colour; F from the Fresnel ramp texture or pow5
//               (spec/003 eq. 7.21, spec/003 eq. 7.22)
//   then        the main light's toon highlight (beyond the thesis; spec/003 eq. 2.1,
//               spec/003 eq. 2.2), and the global fog once (glsl/common/fog.glsl, per fragment)
// Seen from below (the camera under the plane; beyond the thesis): the refraction of what is
// above, tinted by the water colour over the water between the camera and the surface (the
// thickness weight), no reflection, band, highlight or air fog.
// The equations and their guards are in water.glsl.
// Failure cases guarded: the distorted sample landing on something in front of the water (an
// object above the surface bleeding into the refraction) falls back to the undistorted
// coordinates; the scene depth 1 (nothing drawn: the sky) is the far plane, not infinity; the
// view vector of a fragment at the camera falls back (SafeNormalize); see water.glsl.
#include "water.glsl"
#include "fog.glsl"

#ifndef WATER_COMPLEX
#define WATER_COMPLEX 1
#endif
#ifndef WATER_FRESNEL_RAMP
#define WATER_FRESNEL_RAMP 1
#endif

in vec4 vWorldPos;
in vec3 vRel;

uniform vec3 uCameraPos;
uniform vec2 uViewport;          // the target's size in pixels
uniform vec2 uNearFar;           // the camera's near and far planes [m]
uniform float uTime;
uniform int uFogMethod;          // 0 document, 1 repository, 2 thickness (toon_water.fog_method)
uniform vec3 uLightDir;          // toward the main light (unit)
uniform vec3 uLightRadiance;
uniform vec3 uAmbient;           // the sky's ambient radiance
uniform sampler2D uGrab;         // the grab pass: a float copy of the image drawn so far
uniform sampler2D uSceneDepth;   // its depth (window depth, a copy: the water writes depth)
uniform sampler2D uWaveNormals;  // the tileable normal map, 0.5·n + 0.5, mipmapped
uniform sampler2D uFresnelRamp;  // spec/003 eq. 7.22 baked, W × 1
uniform samplerCube uEnvironment;// the sky's reflection probe (without the sun disk)

out vec4 fragColor;

// The depth fog's weight at screen coordinates uv for a water fragment at view depth zWater
// whose view ray is rayPerDepth metres long per metre of view depth.
float DepthFogWeight(float rawDepth, float zWater, float rayPerDepth) {
    if (!uDepthFog) return 0.0;
    if (uFogMethod == 0) return FogWeightDocument(rawDepth, uWaterFogIntensity);
    float zScene = ViewDepth(rawDepth, uNearFar);
    if (uFogMethod == 1) return FogWeightRepository(zScene / uNearFar.y, uWaterFogIntensity);
    return FogWeightThickness((zScene - zWater) * rayPerDepth, uWaterFogIntensity);
}

void main() {
    vec3 up = vec3(0.0, 1.0, 0.0);
    bool below = uCameraPos.y < vWorldPos.y;
    float dist = length(vRel);
    vec3 v = SafeNormalize(-vRel, below ? -up : up);
    vec2 uv1, uv2;
    WaveUVs(vWorldPos.xz, uTime, uWaveTile, uWaveScale, uWaterSpeed, uv1, uv2);
    vec3 n = WaveNormal(texture(uWaveNormals, uv1), texture(uWaveNormals, uv2), uWaveIntensity);
    if (below) n = -n;  // the face the camera sees
    float nv = saturate(dot(n, v));

    // the grab and the depth at one pair of coordinates (ScreenUV: one flip for both)
    float zWater = 1.0 / gl_FragCoord.w;  // clip w: metres along the camera's axis
    vec2 uv = ScreenUV(gl_FragCoord.xy + RefractionOffset(n, uWaveIntensity) * uViewport,
                       uViewport, uFlipY);
    float rawDepth = texture(uSceneDepth, uv).r;
    if (ViewDepth(rawDepth, uNearFar) < zWater) {  // in front of the water: undistorted
        uv = ScreenUV(gl_FragCoord.xy, uViewport, uFlipY);
        rawDepth = texture(uSceneDepth, uv).r;
    }
    vec3 refr = texture(uGrab, uv).rgb;
    vec3 light = WaterLight(uColor, uLightDir, uLightRadiance, uAmbient);
    float w = below ? (uDepthFog ? FogWeightThickness(dist, uWaterFogIntensity) : 0.0)
                    : DepthFogWeight(rawDepth, zWater, dist / max(zWater, 1e-6));
    vec3 refraction = WaterRefraction(refr, light, uRefraction, w);
    if (below) {
        fragColor = vec4(uOutput == 4 ? vec3(w) : refraction, 1.0);
        if (uOutput == 1 || uOutput == 3) fragColor = vec4(0.0, 0.0, 0.0, 1.0);
        return;
    }

    vec3 colour;
    vec3 reflection = vec3(0.0);
    float part;  // the reflectance (Complex) or the band (Simple)
#if WATER_COMPLEX
    reflection = ToonReflection(textureLod(uEnvironment, ReflectionDirection(v, n),
                                           REFLECTION_LOD).rgb, uToonValue);
    if (uReflectionTint) reflection = mix(reflection, light, 0.2);
#if WATER_FRESNEL_RAMP
    part = FresnelWaterRamp(uFresnelRamp, nv);
#else
    part = FresnelWaterPow5(nv);
#endif
    colour = mix(refraction, reflection, part);
    float stepX = uToonValue;
#else
    part = SimpleBand(nv);
    colour = refraction + uBandStrength * part * (uLightRadiance * max(uLightDir.y, 0.0)
                                                   + uAmbient);
    float stepX = 1.0 / 3.0;
#endif
    colour += uHighlight * ToonHighlight(n, v, uLightDir, uHighlightExponent, stepX)
              * uLightRadiance;
    colour = FogApply(colour, vWorldPos.w, vWorldPos.xyz);
    if (uOutput == 1) colour = reflection;
    else if (uOutput == 2) colour = refraction;
    else if (uOutput == 3) colour = vec3(part);
    else if (uOutput == 4) colour = vec3(w);
    fragColor = vec4(colour, 1.0);
}
