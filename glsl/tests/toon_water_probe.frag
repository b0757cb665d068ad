#version 330 core
// Test probe for the toon water's functions (glsl/toon_water/water.glsl, spec/003 §2.10):
// evaluates them at the points of uPoints (one per pixel), so tests/gl/test_toon_water.py
// compares them with the numpy twins of app/sim/toon_water.py.
//   uProbeMode 0: p = (u, 0, 0): (FresnelWaterRamp(uRamp, u), FresnelWaterPow5(u),
//                 SimpleBand(u), 0) — spec/003 eq. 7.21, spec/003 eq. 7.22
//              1: p = a colour: (ToonReflection(p, uToonValue), 0) — spec/003 eq. 7.18,
//                 spec/003 eq. 7.19, spec/003 eq. 7.20
//              2: p = (raw depth, water view depth, ray metres per view metre):
//                 (FogWeightDocument, FogWeightRepository(ViewDepth/far), FogWeightThickness,
//                 ViewDepth) with uWaterFogIntensity and uNearFar
//              3: p = (x, z, t) world: (WaveNormal of the two WaveUVs samples of uNormals, 0)
//              4: p = (fragment x, y, t): (ScreenUV(p.xy, uViewport, uFlipY),
//                 TideLevel(uSeaLevel, uTideHeight, t), 0)
//              5: p = v: (ReflectionDirection(v, uNormal), ToonHighlight(uNormal, v, uLight,
//                 uHighlightExponent, uToonValue))
//              6: p = a refraction colour: (WaterRefraction(p, uColour, uRefraction, uWeight), 0)
// Failure cases: none of its own — those guarded are water.glsl's (its header).
#include "../toon_water/water.glsl"

uniform sampler2D uPoints;
uniform sampler2D uRamp;
uniform sampler2D uNormals;
uniform int uProbeMode;
uniform vec2 uNearFar;
uniform vec2 uViewport;
uniform float uSeaLevel;
uniform vec3 uNormal;
uniform vec3 uLight;
uniform vec3 uColour;
uniform float uWeight;

out vec4 fragColor;

void main() {
    vec3 p = texelFetch(uPoints, ivec2(gl_FragCoord.xy), 0).xyz;
    if (uProbeMode == 0) {
        fragColor = vec4(FresnelWaterRamp(uRamp, p.x), FresnelWaterPow5(p.x), SimpleBand(p.x),
                         0.0);
    } else if (uProbeMode == 1) {
        fragColor = vec4(ToonReflection(p, uToonValue), 0.0);
    } else if (uProbeMode == 2) {
        float z = ViewDepth(p.x, uNearFar);
        fragColor = vec4(FogWeightDocument(p.x, uWaterFogIntensity),
                         FogWeightRepository(z / uNearFar.y, uWaterFogIntensity),
                         FogWeightThickness((z - p.y) * p.z, uWaterFogIntensity), z);
    } else if (uProbeMode == 3) {
        vec2 uv1, uv2;
        WaveUVs(p.xy, p.z, uWaveTile, uWaveScale, uWaterSpeed, uv1, uv2);
        fragColor = vec4(WaveNormal(textureLod(uNormals, uv1, 0.0), textureLod(uNormals, uv2, 0.0),
                                    uWaveIntensity), 0.0);
    } else if (uProbeMode == 4) {
        fragColor = vec4(ScreenUV(p.xy, uViewport, uFlipY), TideLevel(uSeaLevel, uTideHeight, p.z),
                         0.0);
    } else if (uProbeMode == 5) {
        fragColor = vec4(ReflectionDirection(p, uNormal),
                         ToonHighlight(uNormal, p, uLight, uHighlightExponent, uToonValue));
    } else {
        fragColor = vec4(WaterRefraction(p, uColour, uRefraction, uWeight), 0.0);
    }
}
