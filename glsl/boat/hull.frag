#version 330 core
// The boat lit as the maritime thesis lights it (spec/000 §1.7: the sky's reflection probe lights
// the scene's objects, fig. 4.10): the main light's direct term plus the probe's radiance — its
// blurred mips for the diffuse part, a sharper mip for the gloss of the gelcoat — and a Blinn
// highlight of the sun (the probe is sampled without its sun disk). Beyond the thesis, what
// reads as a boat: painted stripes (a sheer band below the deck edge, a boot stripe at the
// design waterline, antifouling below), a gloss per material (gelcoat, non-skid deck, glass,
// varnished teak, metal), and the hull's contact with the sea (spec/000 §1.3, the water the
// boat floats in): where the water meets each side (uWaterline, sampled on the CPU from the
// frame's water at stations along the hull) the topsides are wet — darker, glossier — a little
// above it, and foamed by the bow wave forward.
// Equations: Lambert E·max(n·l, 0)/π·albedo; Schlick 1994's Fresnel F = F0 + (1 − F0)(1 − n·v)^5
// (fresnel.glsl) between the diffuse body and the probe's reflection; a normalised Blinn lobe
// (s + 8)/(8π)·(n·h)^s for the sun; wet albedo ×0.6 (water filling the surface's pores).
// Failure cases guarded: a back face seen through a gap is shaded with its flipped normal
// (two-sided); the mip level is clamped to the cubemap's levels; negative radiance clamped to 0;
// without a probe (uUseProbe false) a flat sky-grey ambient; the waterline index is clamped to
// its stations.
in vec3 vRel;
in vec3 vNormal;
in vec3 vColor;
in vec3 vBoatPos;
in vec3 vExtra;

uniform samplerCube uEnvironment;
uniform float uEnvironmentLods;   // mip levels of the cubemap − 1
uniform bool uUseProbe;
uniform vec3 uMainLightDir;       // toward the light
uniform vec3 uMainLightRadiance;  // irradiance on a surface facing it
uniform vec2 uBootTop;            // (antifouling up to, boot stripe up to) m above the keel
uniform vec3 uBottomColor;        // antifouling, linear
uniform vec3 uStripeColor;        // the boot stripe
uniform vec2 uSheerStripe;        // the sheer band: from, to [m below the deck edge]
uniform vec3 uSheerColor;
uniform float uGloss;             // 0 matte … 1 mirror-like gelcoat
uniform float uTime;
uniform float uWaterline[18];     // where the water meets the hull: port 0–8, starboard 9–17
uniform vec2 uStations;           // z of the first and the last station [m, boat frame]
uniform float uBowWave;           // height of the bow wave's foam at the stem [m]

out vec4 fragColor;

#include "math.glsl"
#include "fresnel.glsl"

const int STATIONS = 9;

float Hash12(vec2 p) {
    vec3 p3 = fract(vec3(p.xyx) * 0.1031);
    p3 += dot(p3, p3.yzx + 33.33);
    return fract((p3.x + p3.y) * p3.z);
}

float ValueNoise(vec2 p) {
    vec2 i = floor(p);
    vec2 f = fract(p);
    vec2 u = f * f * (3.0 - 2.0 * f);
    return mix(mix(Hash12(i), Hash12(i + vec2(1.0, 0.0)), u.x),
               mix(Hash12(i + vec2(0.0, 1.0)), Hash12(i + vec2(1.0, 1.0)), u.x), u.y);
}

// Height of the water against the hull at boat-frame (x, z): linear between the stations,
// blended across the centreline between the two sides.
float WaterlineAt(float x, float z) {
    float t = clamp((z - uStations.x) / max(uStations.y - uStations.x, 1e-3), 0.0, 1.0)
            * float(STATIONS - 1);
    int i = min(int(floor(t)), STATIONS - 2);
    float f = t - float(i);
    float port = mix(uWaterline[i], uWaterline[i + 1], f);
    float stbd = mix(uWaterline[STATIONS + i], uWaterline[STATIONS + i + 1], f);
    return mix(port, stbd, smoothstep(-0.25, 0.25, x));
}

void main() {
    vec3 n = normalize(vNormal);
    if (!gl_FrontFacing) n = -n;
    vec3 v = normalize(-vRel);
    vec3 albedo = vColor;
    int material = int(vExtra.y + 0.5);
    float ao = vExtra.z;
    // gloss per material: gelcoat, non-skid deck, glass, varnished wood, metal
    float gloss = material == 0 ? uGloss : material == 1 ? 0.12 : material == 2 ? 0.95
                : material == 3 ? 0.3 : 0.55;
    float foam = 0.0;
    if (material == 0) {
        float y = vBoatPos.y;
        float below = vExtra.x;
        if (below >= uSheerStripe.x && below < uSheerStripe.y) albedo = uSheerColor;
        if (y < uBootTop.x) albedo = uBottomColor;
        else if (y < uBootTop.y) albedo = uStripeColor;
        // contact with the sea: wet above the water's line, the bow wave's foam forward
        float wl = WaterlineAt(vBoatPos.x, vBoatPos.z);
        float ragged = ValueNoise(vec2(vBoatPos.z * 5.0 + 17.0 * step(0.0, vBoatPos.x),
                                       uTime * 1.5));
        float wetTop = wl + 0.12 + 0.22 * ragged;
        float wet = 1.0 - smoothstep(wl, wetTop, y);
        albedo *= mix(1.0, 0.6, wet);
        gloss = mix(gloss, 0.92, wet);
        float bow = smoothstep(0.6, 3.4, vBoatPos.z);
        float spray = ValueNoise(vec2(vBoatPos.z * 9.0, y * 14.0 - uTime * 3.0));
        float foamTop = wl + 0.025 + uBowWave * bow * (0.45 + 0.9 * ragged);
        foam = (1.0 - smoothstep(foamTop - 0.03, foamTop, y)) * step(wl - 0.08, y)
             * mix(0.55, 1.0, spray) * (0.5 + 0.5 * bow);
    }
    float lods = max(uEnvironmentLods, 0.0);
    vec3 ambient = uUseProbe ? textureLod(uEnvironment, n, lods).rgb : vec3(0.3, 0.35, 0.4);
    vec3 r = reflect(-v, n);
    vec3 reflected = uUseProbe ? textureLod(uEnvironment, r, (1.0 - gloss) * lods).rgb
                               : vec3(0.3, 0.35, 0.4);
    float nl = max(dot(n, uMainLightDir), 0.0);
    vec3 diffuse = albedo * (ambient * ao + uMainLightRadiance * nl / PI);
    float F = SchlickFresnel(0.04, max(dot(n, v), 0.0)) * gloss;
    vec3 h = normalize(uMainLightDir + v);
    float shininess = mix(8.0, 256.0, gloss);
    vec3 highlight = uMainLightRadiance * F * pow(max(dot(n, h), 0.0), shininess)
                     * (shininess + 8.0) / (8.0 * PI) * step(0.0, dot(n, uMainLightDir));
    vec3 c = mix(diffuse, reflected * ao, F) + highlight;
    // foam: a white Lambert scatterer in the sky's and the sun's light
    vec3 foamLit = vec3(0.9) * (ambient + uMainLightRadiance * max(uMainLightDir.y, 0.0) / PI);
    c = mix(c, foamLit, clamp(foam, 0.0, 1.0));
    fragColor = vec4(max(c, vec3(0.0)), 1.0);
}
