#version 330 core
// The boat lit as the maritime thesis lights it (spec/000 §1.7: the sky's reflection probe lights
// the scene's objects, fig. 4.10): the main light's direct term plus the probe's radiance — its
// blurred mips for the diffuse part, a sharper mip for the gloss of the gelcoat — and a Blinn
// highlight of the sun (the probe is sampled without its sun disk).
// Equations: Lambert E·max(n·l, 0)/π·albedo; Schlick 1994's Fresnel F = F0 + (1 − F0)(1 − n·v)^5
// (fresnel.glsl) between the diffuse body and the probe's reflection; the bottom paint below the
// design waterline (uBootTop, a boot stripe above it).
// Failure cases guarded: a back face seen through a gap is shaded with its flipped normal
// (two-sided); the mip level is clamped to the cubemap's levels; negative radiance clamped to 0;
// without a probe (uUseProbe false) a flat sky-grey ambient.
in vec3 vRel;
in vec3 vNormal;
in vec3 vColor;
in float vBoatY;

uniform samplerCube uEnvironment;
uniform float uEnvironmentLods;   // mip levels of the cubemap − 1
uniform bool uUseProbe;
uniform vec3 uMainLightDir;       // toward the light
uniform vec3 uMainLightRadiance;  // irradiance on a surface facing it
uniform vec2 uBootTop;            // (bottom paint up to, boot stripe up to) m above the keel
uniform vec3 uBottomColor;        // antifouling, linear
uniform vec3 uStripeColor;
uniform float uGloss;             // 0 matte … 1 mirror-like gelcoat

out vec4 fragColor;

#include "math.glsl"
#include "fresnel.glsl"

void main() {
    vec3 n = normalize(vNormal);
    if (!gl_FrontFacing) n = -n;
    vec3 v = normalize(-vRel);
    vec3 albedo = vColor;
    if (vBoatY < uBootTop.x) albedo = uBottomColor;
    else if (vBoatY < uBootTop.y) albedo = uStripeColor;
    float lods = max(uEnvironmentLods, 0.0);
    vec3 ambient = uUseProbe ? textureLod(uEnvironment, n, lods).rgb : vec3(0.3, 0.35, 0.4);
    vec3 r = reflect(-v, n);
    vec3 reflected = uUseProbe ? textureLod(uEnvironment, r, (1.0 - uGloss) * lods).rgb
                               : vec3(0.3, 0.35, 0.4);
    float nl = max(dot(n, uMainLightDir), 0.0);
    vec3 diffuse = albedo * (ambient + uMainLightRadiance * nl / 3.14159265);
    float F = SchlickFresnel(0.04, max(dot(n, v), 0.0)) * uGloss;
    vec3 h = normalize(uMainLightDir + v);
    float shininess = mix(8.0, 256.0, uGloss);
    vec3 highlight = uMainLightRadiance * F * pow(max(dot(n, h), 0.0), shininess)
                     * (shininess + 8.0) / (8.0 * 3.14159265) * step(0.0, dot(n, uMainLightDir));
    vec3 c = mix(diffuse, reflected, F) + highlight;
    fragColor = vec4(max(c, vec3(0.0)), 1.0);
}
