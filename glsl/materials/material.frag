#version 330 core
// =============================================================================================
// Procedural solid materials: the thesis's wood (spec/004 §1.4–1.7) and, beyond it, marble and
// granite, each with the thesis's value noise or Perlin's gradient noise (the "noise" switch).
// Unlit by default, as in the thesis (§1.6: no lighting); a toggle adds Blinn–Phong.
// Defines: OUTPUT_OBJECT_POSITION writes the interpolated object position instead of a colour
// (tests check object-space anchoring with it); OUTPUT_RING_RADIUS writes the wood radius.
// =============================================================================================
#include "math.glsl"
#include "noise_value.glsl"
#include "noise_perlin.glsl"
#include "wood.glsl"
#include "stone.glsl"
#include "tonemap.glsl"

in vec3 vObjectPos;
in vec3 vWorldPos;
in vec3 vWorldNormal;
out vec4 fragColor;

uniform int uMaterial;    // 0 wood, 1 marble, 2 granite
uniform int uNoiseKind;   // 0 the thesis's value noise, 1 Perlin's gradient noise
uniform int uRecDepth;    // octaves of the wood distortion noise (RecDepth, 1…8)
uniform bool uFilterRings;
uniform bool uLighting;
uniform vec3 uLightDir;   // toward the light
uniform vec3 uLightColor;
uniform float uAmbient;
uniform float uSpecular;
uniform float uShininess;
uniform vec3 uCameraPos;

// Three noise channels in [0, 1]: the wood's distortion source.
vec3 MaterialNoise3(vec3 p, int depth) {
    if (uNoiseKind == 0) return ThesisOctaves(p, depth);
    // Perlin fBm with the thesis's octave weights, one decorrelated lattice offset per channel,
    // mapped from about [−1, 1] to [0, 1].
    vec3 sum = vec3(0.0);
    float total = 0.0, weight = 1.0, scale = 1.0;
    int d = clamp(depth, 1, 8);
    for (int i = 0; i < 8; ++i) {
        if (i >= d) break;
        vec3 q = p * scale;
        sum += weight * vec3(PerlinNoise3(q), PerlinNoise3(q + vec3(31.416, 47.853, 12.793)),
                             PerlinNoise3(q + vec3(-73.156, 19.271, 61.932)));
        total += weight;
        weight *= 0.5;
        scale *= 2.0;
    }
    return clamp(0.5 + 0.5 * sum / total, 0.0, 1.0);
}

float MaterialNoise1(vec3 p) {
    if (uNoiseKind == 0) return ThesisNoise3(p).x * 2.0 - 1.0;
    return PerlinNoise3(p);
}

void main() {
#ifdef OUTPUT_OBJECT_POSITION
    fragColor = vec4(vObjectPos, 1.0);
    return;
#endif
    vec3 albedo;
    if (uMaterial == 0) {
        vec3 noise = MaterialNoise3(WoodNoiseCoords(vObjectPos), uRecDepth);
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
