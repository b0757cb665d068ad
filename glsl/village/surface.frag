#version 330 core
// The village's lit surfaces (spec/003 §1 — which shader goes where — §2.2, §2.3, §2.8, §2.11,
// §2.12), program ProgramSpec("village/surface"): surface.vert + this file. One program, four
// materials chosen per draw by uMaterial (or VILLAGE_MATERIAL):
//   0 terrain  the island, parallax-mapped ("terreno del proyecto", spec/003 §1): the relief
//              map's uv is the world xz / the relief tile, moved by ParallaxUV (parallax.glsl:
//              spec/003 eq. 3.14, spec/003 eq. 3.15, spec/003 eq. 3.16, spec/003 eq. 3.17),
//              then bumped (bump.glsl: spec/003 eq. 3.1, spec/003 eq. 3.3, spec/003 eq. 3.10),
//              the bump weighted by the vertex's relief weight (paths and rock fully, meadow and
//              sand less); albedo the per-vertex splat
//   1 walls    the houses (ComplexCelShader): the mask texture through the wall's uv — R the
//              emission (the lit windows, spec/003 Fig. 131), G the specular mask, B the window
//              frames (darker albedo) —, the wall's relief (planks) parallax-mapped like the
//              terrain
//   2 solids   the props, roofs, posts (CelShader): the vertex's masks (the barrels' iron hoops
//              carry the specular mask)
//   3 emissive the lanterns' glass and the bonfire's flame: the vertex's emission mask times
//              uEmissionColor (zero when the lamps are off), flickering by uFlicker
// Lighting: ShadeSurfaceShadowed of lighting.glsl (the toon modes of spec/003 §2.12 with
// spec/003 eq. 8.1, the ForwardBase + ForwardAdd sum of the sun and four point lights: three street
// lamps and the bonfire), the sun's shadow visibility from shadow.glsl (the shared shadow
// module, spec/003 §2.8) as the sun's attenuation; then the fog, once, after the lighting
// (FogApply: lerp(fogColour, colour, f), the operands swapped as spec/003 §2.11 says).
// Failure cases guarded: the interpolated normal and tangent re-normalised (SafeNormalize); a
// fragment at the camera keeps a defined view vector; the relief scale kept above zero; a face
// seen from behind (the roofs' undersides are their own faces, but the terrain seen from below
// the sea or a wall from inside) is shaded with its normal turned toward the camera, so it is
// not lit through; the emission is never negative.
#include "lighting.glsl"
#include "parallax.glsl"
#include "shadow.glsl"
#include "fog.glsl"

in vec4 vWorldPos;
in vec3 vWorldNormal;
in vec4 vWorldTangent;
in vec2 vUV;
in vec3 vColour;
in vec2 vMask;

uniform vec3 uCameraPos;
uniform vec3 uCameraForward;
uniform int uMaterial;          // 0 terrain, 1 walls, 2 solids, 3 emissive
// VILLAGE_MATERIAL, when defined, is the material as a constant (the effect draws each with its
// own program on a software rasteriser, which would run every material's code for each)
#ifdef VILLAGE_MATERIAL
#define MATERIAL VILLAGE_MATERIAL
#else
#define MATERIAL uMaterial
#endif
uniform bool uUseRelief;        // parallax and bump with uNormalMap / uHeightMap
uniform sampler2D uNormalMap;   // tangent-space normals of the relief (0.5·n + 0.5)
uniform sampler2D uHeightMap;   // the relief's height in alpha
uniform float uReliefTile;      // metres (terrain) or uv units (walls) per tile of the relief
uniform vec3 uFrameColour;      // the window frames' albedo (walls)
// uDebug: 0 the image, 1 each draw's group as a flat colour, 2 the sun's shadow visibility;
// uDebugId: the draw's group, 0 terrain, 1 walls, 2 solids, 3 lanterns, 4 flame, 5 people.
uniform int uDebug;
uniform int uDebugId;

// A flat colour per group for the debug view (their ids on the three channels: exact to read).
vec3 DebugGroupColour(int id) {
    return vec3(float(id & 1), float((id >> 1) & 1), float((id >> 2) & 1)) * 0.8 + 0.1;
}

out vec4 fragColor;

void main() {
    vec3 p = vWorldPos.xyz;
    vec3 v = SafeNormalize(uCameraPos - p, vec3(0.0, 1.0, 0.0));
    vec3 n = SafeNormalize(vWorldNormal, vec3(0.0, 1.0, 0.0));
    if (dot(n, v) < 0.0 && MATERIAL != 3) n = -n;  // seen from behind
    vec3 albedo = vColour;
    float specMask = vMask.y;
    float emissionMask = vMask.x;
    vec2 uv = vUV;
    if (MATERIAL == 0) {
        specMask = 0.0;
        emissionMask = 0.0;
    }
    if (uUseRelief && (MATERIAL == 0 || MATERIAL == 1)) {
        float tile = max(uReliefTile, 1e-3);
        vec2 ruv = (MATERIAL == 0 ? p.xz : vUV) / tile;
        mat3 tbn = BumpTangentFrame(n, vWorldTangent);
        ruv = ParallaxUV(uHeightMap, ruv, TangentSpaceView(v, tbn));
        vec3 bumped = BumpedNormal(uNormalMap, ruv, n, vWorldTangent);
        float weight = MATERIAL == 0 ? clamp(vMask.y, 0.0, 1.0) : 1.0;
        n = SafeNormalize(mix(n, bumped, weight), n);
        if (MATERIAL == 1) uv = ruv * tile;  // the windows move with the relief
    }
    if (MATERIAL == 1) {
        vec4 masks = texture(uMasks, uv);
        emissionMask = masks.r;
        specMask = masks.g;
        albedo = mix(albedo, uFrameColour, masks.b);
        albedo = mix(albedo, vec3(0.05, 0.07, 0.09), masks.r);  // the glass, dark by day
    }
    float viewDepth = dot(p - uCameraPos, uCameraForward);
    float sunVisibility = ShadowSun(p, n, viewDepth);
    vec3 colour;
    if (MATERIAL == 3) {
        colour = albedo * uAmbient + max(uEmissionColor, vec3(0.0)) * emissionMask
                 * FlickerFactor(uTime, uFlicker);
    } else {
        colour = ShadeSurfaceShadowed(p, n, v, albedo, specMask, emissionMask, sunVisibility);
    }
    fragColor = vec4(FogApply(max(colour, vec3(0.0)), vWorldPos.w, p), 1.0);
    if (uDebug == 1) fragColor = vec4(DebugGroupColour(uDebugId), 1.0);
    if (uDebug == 2) fragColor = vec4(vec3(sunVisibility), 1.0);
}
