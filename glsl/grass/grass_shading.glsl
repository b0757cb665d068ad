// =============================================================================================
// The grass's light, shared by the fragment stages of glsl/grass/ (spec/003 §2.9): the
// document's fragment shader computes "only the diffuse reflection of the light" (Lambert,
// spec/003 §2.1: k_diff = n·l), lit by the village's main light (the sky's sun by day, its moon
// by night) plus the sky's ambient; the sun's shadow received through shadow.glsl (the frame's
// published maps: ShadowSun) on the direct term; then the global fog, once, after the lighting
// (fog.glsl: FogApply(colour, factor, p), the factor carried per vertex in the w of the world
// position, spec/003 eq. 7.24, spec/003 eq. 7.27, spec/003 eq. 7.28, spec/003 eq. 7.29).
//
//   document     c = albedo·(ambient + E·vis·max(n·l, 0)) + albedo·E·vis·τ·max(−n·l, 0)
//   repository   c = albedo·E·(f + (1 − f)·vis·saturate(n·l))   (GeometryGrass f = 0.5,
//                    Grass_CrossBillboard f = 0.7: Unity's _LightColor0·_Color·(f + …))
// E the light's radiance, vis the sun's shadow visibility, τ the translucency (the instanced
// blades' light through the leaf, beyond the thesis; 0 for the other methods). The grass casts
// no shadow of its own (it is not drawn into the shadow maps).
//
// Failure cases guarded: the normal is turned toward the camera before lighting (a crossed
// plane or a bent blade seen from behind is lit as its visible side, never through), a zero
// normal becomes +y (SafeNormalize), the light below the horizon gives no direct light, a
// fragment at the camera keeps a defined view vector.
// =============================================================================================
#include "math.glsl"
#include "shadow.glsl"
#include "fog.glsl"

uniform vec3 uLightDir;        // toward the main light (unit)
uniform vec3 uLightRadiance;   // E: the main light's radiance
uniform vec3 uAmbient;         // the sky's ambient radiance
uniform vec3 uCameraPos;
uniform vec3 uCameraForward;
uniform int uLightingModel;    // 0 the document's, 1 the repository's
uniform float uRepositoryFloor; // f of the repository's model (set per method)

// The normal seen from the camera's side of the surface.
vec3 GrassFacingNormal(vec3 n, vec3 p) {
    vec3 nn = SafeNormalize(n, vec3(0.0, 1.0, 0.0));
    vec3 v = uCameraPos - p;
    return dot(nn, v) < 0.0 ? -nn : nn;
}

// The grass's colour, linear radiance after the fog: the document's or the repository's model
// of the header (uLightingModel), for the albedo, the normal n (turned toward the camera), the
// world position in metres with the fog factor in w, and the translucency τ. The sun's shadow
// is read only while the light is above the horizon; the colour is floored at 0.
vec3 GrassShade(vec3 albedo, vec3 n, vec4 worldPos, float translucency) {
    vec3 p = worldPos.xyz;
    vec3 nn = GrassFacingNormal(n, p);
    vec3 l = SafeNormalize(uLightDir, vec3(0.0, 1.0, 0.0));
    float ndl = dot(nn, l);
    float viewDepth = max(dot(p - uCameraPos, uCameraForward), 0.0);
    float vis = l.y > 0.0 ? ShadowSun(p, nn, viewDepth) : 1.0;
    vec3 colour;
    if (uLightingModel == 1) {
        float f = clamp(uRepositoryFloor, 0.0, 1.0);
        colour = albedo * uLightRadiance * (f + (1.0 - f) * vis * saturate(ndl));
    } else {
        colour = albedo * (uAmbient + uLightRadiance * vis * max(ndl, 0.0))
               + albedo * uLightRadiance * vis * max(translucency, 0.0) * max(-ndl, 0.0);
    }
    return FogApply(max(colour, vec3(0.0)), worldPos.w, p);
}
