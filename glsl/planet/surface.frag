#version 330 core
// =============================================================================================
// Surfaces of the planet scene into the G-buffer: Color_original(O) and the camera-relative
// position of O (spec/002 §1.4: the colour that the out-scattering attenuates).
//   texture only (methods 1–2, as the thesis's first versions did)  or
//   Phong (§3.3): ambient = k_a · texture colour (the thesis's modification; beyond the thesis,
//   planet.ambient = sky: the sky's irradiance, planet/sky_irradiance.glsl), diffuse from the
//   normal map, specular (N·H)^n; shadows enter as diffuse = min(shadow, diffuse) (§3.4).
// Beyond the thesis: sunlight reaching the surface is attenuated by the transmittance toward
// the sun (from the optical-depth LUT), so surfaces redden at sunset like the sky does.
// Equations: the thesis numbers none (spec/002 §3.3, §3.4).
// Failure cases guarded: shadow acne on surfaces turned from the sun (the bias grows with
// 1 − N·L); a tangent not perpendicular to the normal (Gram–Schmidt before the normal map);
// no specular highlight on faces turned away from the sun; a sun below this point's horizon
// with no air (β = 0 lets the LUT transmit through the planet): the planet test zeroes it.
// =============================================================================================
#include "atmosphere/model.glsl"
#include "atmosphere/optical_depth_lut.glsl"
#include "atmosphere/sun_transmittance.glsl"
#include "shadow.glsl"
#include "sky_irradiance.glsl"

in vec3 vRel;
in vec3 vLocal;
in vec3 vNormal;
in vec3 vTangent;
in vec2 vUv;

layout(location = 0) out vec4 outColor;
layout(location = 1) out vec4 outPosition;

uniform sampler2D uAlbedo;
uniform sampler2D uNormalMap;
uniform float uTextureTile;     // metres per texture repeat
uniform int uShading;           // 0 texture only, 1 Phong
uniform bool uNormalMapping;
uniform float uKa;
uniform float uKd;
uniform float uKs;
uniform float uShininess;

// The mesh's colour (texture, or Phong lit by the attenuated sun) and its camera-relative
// position, into the G-buffer.
void main() {
    vec3 albedo = texture(uAlbedo, vUv / uTextureTile).rgb;
    vec3 color = albedo;
    if (uShading == 1) {
        vec3 n = normalize(vNormal);
        if (uNormalMapping) {
            vec3 t = normalize(vTangent - n * dot(n, vTangent));
            vec3 b = cross(n, t);
            vec3 m = texture(uNormalMap, vUv / uTextureTile).xyz * 2.0 - 1.0;
            n = normalize(mat3(t, b, n) * m);
        }
        vec3 l = uSunDir;
        vec3 v = normalize(-vRel);
        float nl = max(dot(n, l), 0.0);
        float shadow = ShadowVisibility(vLocal, ShadowSlopeBias(uShadowBias, nl));
        float diffuse = min(shadow, nl);
        float spec = nl > 0.0 ? pow(max(dot(n, normalize(l + v)), 0.0), uShininess) * shadow : 0.0;
        vec3 sunlight = SunTransmittanceAt(vRel);
        // The planet hides a sun below this point's horizon even with no air (β = 0 makes the
        // LUT's "ground" depth transmit, exp(−0 · 1e12) = 1): walls facing it stay unlit.
        vec3 fromCentre = vRel - uEarthCenter;
        float r = length(fromCentre);
        if (SunRayHitsGround(r - uBottomRadius, dot(fromCentre / r, uSunDir))) sunlight = vec3(0.0);
        color = AmbientLight(albedo, n, uKa, uKd)
                + (albedo * uKd * diffuse + uKs * spec) * sunlight;
    }
    outColor = vec4(color, 1.0);
    outPosition = vec4(vRel, 1.0);
}
