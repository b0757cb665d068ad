#version 330 core
// The lit surface of the shading lab (spec/003 §2.1 lighting models, spec/003 §2.12 CelShader
// and ComplexCelShader), program ProgramSpec("shading/surface"): surface.vert + this file.
// Equations (tagged in lighting.glsl and staircase.glsl): spec/003 eq. 2.1, spec/003 eq. 2.2,
// spec/003 eq. 8.1, and the Stepped specular's soft staircase (spec/003 eq. 8.4); the models
// without numbers (Lambert, Phong, rim, Stepped, Flat) by section.
//
// Interface (all an effect sets; nothing else is read):
//   vertex inputs  in_position (vec3), in_normal (vec3), in_uv (vec2), in_tangent (vec4: xyz
//                  the +u tangent, w the handedness)
//   transforms     uModel (mat4: rotation, translation, uniform scale), uViewProj (mat4),
//                  uCameraPos (vec3, world)
//   lights         uSunDir (toward the light), uSunRadiance; uPointPos[4], uPointRadiance[4],
//                  uPointRange[4], uPointCount; uSpotPos, uSpotDir (its axis, outward),
//                  uSpotRadiance, uSpotCos (vec2: inner, outer cosines), uSpotRange (≤ 0: no
//                  falloff), uSpotOn; uAmbient (radiance, added once)
//   material       uAlbedo (linear), uRamp (sampler2D, the W × 1 ramp), uMasks (sampler2D: R
//                  emission, G specular), uUseMasks, uTime (seconds); uUseMaps with uNormalMap
//                  and uHeightMap (bump.glsl, parallax.glsl: spec/003 eq. 3.3, spec/003 eq. 3.4
//                  and the parallax methods), uUseAlbedoMap with uAlbedoMap
//   parameters     (// @param, group shading) uLightingModel, uPhongExponent, uBlinnExponent,
//                  uRim, uRimPower, uRimColor, uToon, uSteppedRepository, uSpecularity,
//                  uSmoothness, uEmissionColor, uFlicker (lighting.glsl), uGouraud (surface.vert)
//   output         fragColor: linear radiance, alpha 1
//   shadows        the sun's shadow uniforms of shadow.glsl (spec/003 §2.8; uShadowSunEnabled
//                  false: fully lit) and uCameraForward (vec3, the view depth of the cascades)
// The light sum is ForwardBase (ambient, sun with its shadow visibility, rim, emission) +
// ForwardAdd (each point light and the spot, unshadowed), as lighting.glsl's header describes.
//
// Failure cases guarded: the interpolated normal and tangent are re-normalised per fragment
// (interpolation shortens them), with safe fallbacks for zero vectors; a fragment at the camera
// position keeps a defined view vector; see lighting.glsl for the guards of the models (light
// exactly behind, grazing light, equal spot cosines). The Gouraud path (uGouraud) shows the
// thesis's failure on purpose: a coarse mesh loses or smears its highlight.
#include "lighting.glsl"
#include "parallax.glsl"  // and bump.glsl: spec/003 §2.2 and §2.3 on the surfaces with maps
#include "shadow.glsl"    // the sun's shadow of the objects (spec/003 §2.8)

in vec3 vWorldPos;
in vec3 vWorldNormal;
in vec4 vWorldTangent;
in vec2 vUV;
in vec3 vGouraud;

uniform vec3 uCameraPos;
uniform vec3 uCameraForward;
uniform bool uGouraud;
uniform bool uUseMaps;          // this object has a normal and a height map (the brick wall)
uniform sampler2D uNormalMap;   // tangent-space normals, 0.5·n + 0.5 (or DXT5nm)
uniform sampler2D uHeightMap;   // height in alpha
uniform bool uUseAlbedoMap;
uniform sampler2D uAlbedoMap;   // linear albedo, replacing uAlbedo

out vec4 fragColor;

void main() {
    if (uGouraud) {
        fragColor = vec4(vGouraud, 1.0);
        return;
    }
    vec3 v = SafeNormalize(uCameraPos - vWorldPos, vec3(0.0, 0.0, 1.0));
    vec3 n = SafeNormalize(vWorldNormal, v);
    vec2 uv = vUV;
    vec3 albedo = uAlbedo;
    if (uUseMaps) {
        // parallax first (every later read uses the offset uv), then the bumped normal
        mat3 tbn = BumpTangentFrame(n, vWorldTangent);
        uv = ParallaxUV(uHeightMap, uv, TangentSpaceView(v, tbn));
        n = BumpedNormal(uNormalMap, uv, n, vWorldTangent);
    }
    if (uUseAlbedoMap) albedo = texture(uAlbedoMap, uv).rgb;
    vec4 masks = uUseMasks ? texture(uMasks, uv) : vec4(0.0, 1.0, 0.0, 0.0);
    // the geometric normal offsets the shadow lookup (the bumped one would tear the relief)
    float sun = ShadowSun(vWorldPos, SafeNormalize(vWorldNormal, v),
                          dot(vWorldPos - uCameraPos, uCameraForward));
    fragColor = vec4(ShadeSurfaceShadowed(vWorldPos, n, v, albedo, masks.g, masks.r, sun), 1.0);
}
