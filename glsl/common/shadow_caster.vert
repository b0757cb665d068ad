#version 330 core
// The shared shadow caster (spec/003 §2.8, Unity's "ShadowCaster" pass), program
// ProgramSpec("common/shadow_caster"): this file + shadow_caster.frag, drawn by
// app.render.shadow_maps for directional cascades, spot and point maps.
// Equations: the normal bias of UnityClipSpaceShadowCasterPos — the caster moves inward along
// −n by sin(l, n) × normal bias × the texel's world size — and the linear bias of
// UnityApplyLinearShadowBias, here a push of linear bias × texel along −l (twin:
// app/sim/shadows.py normal_bias_offset, linear_bias_offset).
// Interface: in_position, in_normal (world space), in_uv; uShadowCasterViewProj (world → the
// light's clip), uShadowCasterLight (toward the light for kind 0, the light's position for 1
// and 2), uShadowCasterKind (0 directional, 1 spot, 2 point), uShadowCasterTexel (a texel's
// world size: metres for kind 0, metres per metre of distance for 1 and 2), the two biases in
// texels.
// Failure cases guarded: sin from cos = n·l is clamped (never NaN at n ∥ l); a zero normal or a
// vertex at the light's position keeps its place (no normalise of zero).
#include "math.glsl"

in vec3 in_position;
in vec3 in_normal;
in vec2 in_uv;

uniform mat4 uShadowCasterViewProj;
uniform vec3 uShadowCasterLight;
uniform int uShadowCasterKind;
uniform float uShadowCasterTexel;
uniform float uShadowCasterNormalBias;
uniform float uShadowCasterLinearBias;

out vec3 vWorld;
out vec2 vUV;


void main() {
    vec3 p = in_position;
    vec3 n = SafeNormalize(in_normal, vec3(0.0));
    vec3 toLight = uShadowCasterKind == 0 ? SafeNormalize(uShadowCasterLight, vec3(0.0))
                                          : uShadowCasterLight - p;
    float dist = length(toLight);
    vec3 l = uShadowCasterKind == 0 ? toLight : SafeNormalize(toLight, vec3(0.0));
    float texel = uShadowCasterKind == 0 ? uShadowCasterTexel : uShadowCasterTexel * dist;
    float c = clamp(dot(n, l), -1.0, 1.0);
    float s = sqrt(max(1.0 - c * c, 0.0));
    p -= n * s * uShadowCasterNormalBias * texel;
    if (uShadowCasterKind != 2) p -= l * uShadowCasterLinearBias * texel;
    vWorld = p;
    vUV = in_uv;
    gl_Position = uShadowCasterViewProj * vec4(p, 1.0);
}
