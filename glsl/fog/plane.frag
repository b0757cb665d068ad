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
// Failure cases guarded: fragments whose alpha is 0 are discarded (nothing to blend: no
// invisible fragments written); the plane seen from below (a camera under it) is lit with its
// normal turned toward the camera, not through; the cutoff and alpha saturated (plane.glsl).
#include "plane.glsl"
#include "fog.glsl"

in vec4 vWorldPos;
in vec2 vUV;
in vec2 vMaskUV;

uniform sampler2D uFogTexture;   // RGB the wisps' shade, A their coverage (tileable)
uniform sampler2D uGroundMask;   // R: 1 where the ground lies just below the plane
uniform float uCutoff;           // FogGenerator's _Cutoff = 1 − Fog Intensity
uniform float uTime;             // seconds (Unity's _Time.y)
uniform vec3 uCameraPos;
uniform vec3 uLightDir;          // toward the main light
uniform vec3 uLightRadiance;     // the main light's radiance
uniform vec3 uAmbient;           // the sky's ambient radiance

out vec4 fragColor;

void main() {
    vec4 tex = texture(uFogTexture, vUV);
    float mask = texture(uGroundMask, vMaskUV).r;
    float alpha = FogPlaneAlpha(tex.a, FogPlaneCutoff(uCutoff, uTime), mask);
    if (alpha <= 0.0) discard;
    vec3 n = vec3(0.0, uCameraPos.y >= vWorldPos.y ? 1.0 : -1.0, 0.0);
    float ndotl = clamp(dot(n, uLightDir), 0.0, 1.0);
    vec3 colour = tex.rgb * (uLightRadiance * (0.7 + 0.3 * ndotl) + uAmbient);
    fragColor = vec4(FogApply(colour, vWorldPos.w, vWorldPos.xyz), alpha);
}
