// Ocean shading (spec/000 §1.2, the thesis's OceanShader from gasgiant/FFT-Ocean, and §1.7's
// reflection probe): Fresnel (Schlick, n = 1.333 → F0 = 0.0204) between the sky's environment
// cubemap and the water body's upwelling light; the main light's specular (sun by day, moon by
// night: the thesis's main-light parameter, §1.2 change 2 — one light, so no double highlights);
// foam; haze toward the horizon colour; and, seen from below, Snell's window with total internal
// reflection beyond the critical angle (48.6°).
// Glitter: a Beckmann lobe whose slope variance is what the geometry cannot show — the floor below,
// the unresolved remainder of Cox–Munk's mean-square slope (uSubgridMss, from the CPU) and the
// slopes filtered out for this pixel (lostMss) — so the highlight keeps its energy at a distance.
// Guards: n·v and n·l clamped before division, reflections below the horizon folded up (the sea
// does not reflect itself), the cubemap LOD clamped to the map's levels.

#include "math.glsl"
#include "fresnel.glsl"
#include "sea_plane.glsl"  // SEA_F0 = ((n − 1)/(n + 1))² and SeaBeckmann, shared with the skies' sea

uniform samplerCube uEnvironment;
uniform float uEnvironmentLods;      // mip levels of the cubemap − 1
uniform vec3 uMainLightDir;          // toward the light (sun or moon)
uniform vec3 uMainLightRadiance;
uniform float uSubgridMss;           // unresolved mean-square slope (CPU: Cox–Munk − resolved)

uniform bool uReflections;     // @param true §1.7 reflect the sky's environment cubemap (the thesis's reflection probe); off: a flat sky colour
uniform vec3 uScatterColor;    // @param (0.01, 0.045, 0.06) [0, 1] color §1.2 water body colour: upwelling radiance per unit of sky radiance
uniform float uSubsurface;     // @param 1.0 [0, 5] step=0.05 §1.2 light through the wave crests, seen against the light
uniform vec3 uFoamColor;       // @param (0.9, 0.9, 0.9) [0, 1] color §1.2 foam albedo
uniform float uMssFloor;       // @param 0.002 [0, 0.1] step=0.0005 smallest slope variance of the glitter lobe
uniform vec3 uUnderwaterColor; // @param (0.1, 0.55, 0.6) [0, 1] color §1.2 colour of the light scattered by the water, seen from inside
uniform float uUnderwaterClarity; // @param 0.5 [0.01, 1] step=0.01 §1.2 the thesis's underwater clarity: 0 = murky (2 m visibility), 1 = clear (80 m)
uniform float uHazeDistance;   // @param 12000 [100, 100000] step=100 unit=m distance over which the sea fades into the horizon colour

const float WATER_IOR = 1.333;

vec3 EnvironmentRadiance(vec3 dir, float lod) {
    if (!uReflections) return vec3(0.25, 0.3, 0.35) * max(uMainLightRadiance.g, 0.02);
    dir.y = abs(dir.y);
    return textureLod(uEnvironment, dir, clamp(lod, 0.0, uEnvironmentLods)).rgb;
}

// Radiance leaving the sea surface toward the viewer, seen from above.
// p: surface point relative to the camera; n: normal; v: unit vector toward the camera;
// crest: wave height in units of the sea's significant height (subsurface light).
vec3 OceanShadeAbove(vec3 p, vec3 n, vec3 v, float foam, float lostMss, float crest) {
    float mss = max(uMssFloor + uSubgridMss + lostMss, 1e-5);
    float nv = max(dot(n, v), 1e-3);
    float F = SchlickFresnel(SEA_F0, nv);
    vec3 r = reflect(-v, n);
    float envLod = log2(max(sqrt(mss) * 128.0, 1.0));
    vec3 reflected = EnvironmentRadiance(r, envLod);

    vec3 l = uMainLightDir;
    vec3 E = uMainLightRadiance;
    vec3 skyAmbient = EnvironmentRadiance(vec3(0.0, 1.0, 0.0), uEnvironmentLods);
    float nl = max(dot(n, l), 0.0);
    vec3 body = uScatterColor * (skyAmbient + E * max(l.y, 0.0) / PI);
    // light through thin crests, seen toward the light
    float back = pow(max(dot(v, -normalize(vec3(l.x, 0.0, l.z) + vec3(0.0, 1e-4, 0.0))), 0.0), 4.0);
    body += uScatterColor * E * uSubsurface * back * max(crest, 0.0);

    vec3 h = normalize(l + v);
    float nh = max(dot(n, h), 0.0);
    float G = min(1.0, min(2.0 * nh * nv / max(dot(v, h), 1e-3), 2.0 * nh * nl / max(dot(v, h), 1e-3)));
    vec3 spec = E * SchlickFresnel(SEA_F0, dot(v, h)) * SeaBeckmann(nh, mss) * G / (4.0 * nv) * step(0.0, l.y);

    vec3 water = mix(body, reflected, F) + spec;
    vec3 foamLit = uFoamColor * (skyAmbient + E * nl / PI);  // Lambert
    vec3 c = mix(water, foamLit, clamp(foam, 0.0, 1.0));

    float dist = length(p);
    vec3 horizon = EnvironmentRadiance(normalize(vec3(-v.x, 0.02, -v.z)), 2.0);
    return mix(c, horizon, 1.0 - exp(-dist / uHazeDistance));
}

// Seen from below: n is the upward normal, v points down toward the camera.
// transmitted: radiance above the surface along the refracted ray (the scene behind);
// waterLight: the water's own light in the reflected direction (inscattered, from the fog).
vec3 OceanShadeBelow(vec3 n, vec3 v, vec3 transmitted, vec3 waterLight) {
    vec3 nd = -n;                                  // facing the camera, into the water
    float cosI = max(dot(v, nd), 0.0);             // angle in water
    float sinT2 = WATER_IOR * WATER_IOR * (1.0 - cosI * cosI);
    if (sinT2 >= 1.0) return waterLight;           // total internal reflection (Snell's window edge)
    float cosT = sqrt(1.0 - sinT2);                // angle in air: Schlick on the air side
    float F = SchlickFresnel(SEA_F0, cosT);
    return mix(transmitted, waterLight, F);
}

// Under water: extinction σ per channel (1/m) for the clarity — a visibility V in metres where
// green keeps 5 % of the contrast (σ = 3/V); red is absorbed 4× faster, blue a little slower.
vec3 UnderwaterExtinction() {
    float visibility = mix(2.0, 80.0, clamp(uUnderwaterClarity, 0.0, 1.0));
    return 3.0 / visibility * vec3(4.0, 1.0, 0.8);
}

// Radiance the water scatters toward the eye (the fog colour): sky and main light from above.
vec3 UnderwaterLight() {
    vec3 skyAmbient = EnvironmentRadiance(vec3(0.0, 1.0, 0.0), uEnvironmentLods);
    return uUnderwaterColor * 0.1 * (skyAmbient + uMainLightRadiance * max(uMainLightDir.y, 0.0) / PI);
}
