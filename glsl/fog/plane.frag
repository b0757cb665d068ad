#version 330 core
// The ground fog plane (spec/003 §2.11 a, Custom/Fog), program ProgramSpec("fog/plane"):
// plane.vert + this file. A semitransparent material (spec/003 §2.4's alpha blending, Blend
// SrcAlpha OneMinusSrcAlpha, no depth writes) with the generated RGBA fog texture (spec/003
// Fig. 118; app/sim/fog.py fog_texture); its alpha minus the sin(t)-modulated cutoff (plane.glsl)
// makes the fog appear and disappear; lit as the repository's shader lights it,
// tex.rgb·(0.7 + 0.3·saturate(n·l)), by the scene's main light (its radiance: the moon's at
// night, so the plane does not glow in the dark) plus the sky's ambient; then the global fog
// like every surface (fog.glsl: spec/003 eq. 7.27, spec/003 eq. 7.28, spec/003 eq. 7.29), so
// the far end of the plane fades into the distance fog with what it covers.
// Beyond the thesis, four knobs of the plane's opacity (1, 0, 0, 0 by default: the thesis's
// Custom/Fog unchanged; the village's preset sets them): uPlaneOpacity scales the texture's
// alpha; uPlaneBreakup breaks the wisps into drifting banks with clear ground between them (a
// second lookup of the same tileable texture, rotated and PlaneBankScale times coarser, whose
// coverage thins the first — it moves with the same uv scroll, so the banks drift with the wind);
// uPlaneHug thins the wisps where the ground lies less than uPlaneHug below the plane (the mask's
// G channel: the layer's depth over 2 m), so the fog lies in the hollows and fades out before a
// slope rises through it instead of cutting it along a hard line; uPlaneGrazing: the layer is
// thin, so it is seen through little of itself from above and through much of it at a grazing
// angle, (1 − |v·n|)^uPlaneGrazing (from a hill the wisps do not lie on the meadow like snow).
// They multiply the ground mask given to FogPlaneAlpha: the thesis's cutoff and its sin(t)
// modulation are unchanged.
// Failure cases guarded: fragments whose alpha is 0 are discarded (nothing to blend: no
// invisible fragments written); the plane seen from below (a camera under it) is lit with its
// normal turned toward the camera, not through; the cutoff and alpha saturated (plane.glsl).
#include "plane.glsl"
#include "fog.glsl"

in vec4 vWorldPos;
in vec2 vUV;
in vec2 vMaskUV;

uniform sampler2D uFogTexture;   // RGB the wisps' shade, A their coverage (tileable)
// uGroundMask: R 1 where the ground lies just below the plane; G its depth below the plane / 2 m
uniform sampler2D uGroundMask;
uniform float uCutoff;           // FogGenerator's _Cutoff = 1 − Fog Intensity
uniform float uTime;             // seconds (Unity's _Time.y)
uniform vec3 uCameraPos;
uniform vec3 uLightDir;          // toward the main light
uniform vec3 uLightRadiance;     // the main light's radiance
uniform vec3 uAmbient;           // the sky's ambient radiance
uniform float uPlaneOpacity; // @param 1 [0, 1] step=0.01 §2.11 times the fog texture's alpha (1:
                             // the thesis's plane; beyond the thesis)
uniform float uPlaneBreakup; // @param 0 [0, 1] step=0.01 §2.11 breaks the wisps into drifting banks
                             // with clear ground between them (0: the thesis's one texture lookup;
                             // beyond the thesis)
uniform float uPlaneGrazing; // @param 0 [0, 4] step=0.05 §2.11 the wisps thin as the view looks
                             // down on the plane, (1 − |v·n|)^this: a thin layer seen from above
                             // (0: off; beyond the thesis)
uniform float uPlaneHug; // @param 0 [0, 2] step=0.05 unit=m §2.11 the wisps thin where the ground
                         // lies less than this below the plane: fog in the hollows, no hard cut on
                         // slopes (0: off; beyond the thesis)

// the banks' lookup: this many tiles of the wisps per tile of the banks, and turned by 37°
const float PlaneBankScale = 3.4;
const mat2 PlaneBankTurn = mat2(0.8, 0.6, -0.6, 0.8);
// the texture's largest alpha (app/sim/fog.py TEXTURE_MAX_ALPHA)
const float PlaneTextureMaxAlpha = 0.6;

// The modulation of the plane's opacity (1 with the defaults): opacity · view angle · banks · hug.
float FogPlaneModulation(vec2 uv, float depthBelow, float cosView) {
    float m = clamp(uPlaneOpacity, 0.0, 1.0);
    if (uPlaneGrazing > 0.0) m *= pow(clamp(1.0 - abs(cosView), 0.0, 1.0), uPlaneGrazing);
    if (uPlaneBreakup > 0.0) {
        float bank = texture(uFogTexture, PlaneBankTurn * uv / PlaneBankScale + vec2(0.37, 0.61)).a
                     / PlaneTextureMaxAlpha;
        m *= mix(1.0, smoothstep(0.08, 0.75, bank), clamp(uPlaneBreakup, 0.0, 1.0));
    }
    if (uPlaneHug > 0.0) m *= smoothstep(0.0, uPlaneHug, depthBelow);
    return m;
}

out vec4 fragColor;

void main() {
    vec4 tex = texture(uFogTexture, vUV);
    vec2 ground = texture(uGroundMask, vMaskUV).rg;
    vec3 toCamera = uCameraPos - vWorldPos.xyz;
    float cosView = toCamera.y / max(length(toCamera), 1e-6);
    float mask = ground.r * FogPlaneModulation(vUV, 2.0 * ground.g, cosView);
    float alpha = FogPlaneAlpha(tex.a, FogPlaneCutoff(uCutoff, uTime), mask);
    if (alpha <= 0.0) discard;
    vec3 n = vec3(0.0, uCameraPos.y >= vWorldPos.y ? 1.0 : -1.0, 0.0);
    float ndotl = clamp(dot(n, uLightDir), 0.0, 1.0);
    vec3 colour = tex.rgb * (uLightRadiance * (0.7 + 0.3 * ndotl) + uAmbient);
    fragColor = vec4(FogApply(colour, vWorldPos.w, vWorldPos.xyz), alpha);
}
