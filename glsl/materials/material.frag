#version 330 core
// =============================================================================================
// Procedural solid materials: the thesis's wood (spec/004 §1.4–1.7) and, beyond it, marble and
// granite, each with the thesis's value noise or Perlin's gradient noise (the "noise" switch).
// Unlit by default, as in the thesis (§1.6: no lighting); a toggle adds Blinn–Phong.
// Defines: OUTPUT_OBJECT_POSITION writes the interpolated object position instead of a colour
// (tests check object-space anchoring with it); OUTPUT_RING_RADIUS writes the wood radius and
// noise; BAKED_NOISE reads the wood's distortion noise from a 3D texture baked over the object's
// box (wood_noise_bake.*) instead of evaluating it per pixel — the speed/accuracy trade the
// bench measures.
// Equations: the thesis numbers none; the wood is its ring function C∘g∘w (spec/004 §1.4,
// wood.glsl), the noise its value noise (spec/004 §1.5, common/noise_value.glsl).
// Failure cases guarded: ring aliasing under minification (uFilterRings box-filters the ring
// over the pixel footprint from dFdx/dFdy of the radius; a zero footprint falls back to the
// unfiltered ring); the thesis's colours are sRGB-authored and are linearised before lighting;
// the interpolated normal is renormalised, and there is no highlight on faces turned from the
// light. BAKED_NOISE is exact only at texel centres (trilinear between them) and clamps to the
// edge outside the object box [-0.5, 0.5]³.
// =============================================================================================
#include "math.glsl"
#include "material_noise.glsl"
#include "wood.glsl"
#include "stone.glsl"
#include "tonemap.glsl"

in vec3 vObjectPos;
in vec3 vWorldPos;
in vec3 vWorldNormal;
out vec4 fragColor;

uniform int uMaterial;    // 0 wood, 1 marble, 2 granite
uniform bool uFilterRings;
uniform bool uLighting;
uniform vec3 uLightDir;   // toward the light
uniform vec3 uLightColor;
uniform float uAmbient;
uniform float uSpecular;
uniform float uShininess;
uniform vec3 uCameraPos;
#ifdef BAKED_NOISE
uniform sampler3D uBakedNoise;  // MaterialNoise3 over the object box [-0.5, 0.5]³, texel centres
#endif

void main() {
#ifdef OUTPUT_OBJECT_POSITION
    fragColor = vec4(vObjectPos, 1.0);
    return;
#endif
    vec3 albedo;
    if (uMaterial == 0) {
#ifdef BAKED_NOISE
        vec3 noise = texture(uBakedNoise, vObjectPos + 0.5).rgb;
#else
        vec3 noise = MaterialNoise3(WoodNoiseCoords(vObjectPos), uRecDepth);
#endif
        float radius = WoodRadius(vObjectPos, noise);
#ifdef OUTPUT_RING_RADIUS
        fragColor = vec4(radius, noise);
        return;
#endif
        float width = length(vec2(dFdx(radius), dFdy(radius)));
        albedo = SrgbToLinear(WoodColor(WoodRingValue(radius, width, uFilterRings)));
    } else if (uMaterial == 1) {
        albedo = MarbleColor(vObjectPos);
    } else {
        albedo = GraniteColor(vObjectPos);
    }
    vec3 color = albedo;
    if (uLighting) {
        vec3 n = normalize(vWorldNormal);
        vec3 l = normalize(uLightDir);
        vec3 v = normalize(uCameraPos - vWorldPos);
        vec3 h = normalize(l + v);
        float diffuse = max(dot(n, l), 0.0);
        float specular = diffuse > 0.0 ? pow(max(dot(n, h), 0.0), uShininess) : 0.0;
        color = albedo * (uAmbient + diffuse * uLightColor) + uSpecular * specular * uLightColor;
    }
    fragColor = vec4(color, 1.0);
}
