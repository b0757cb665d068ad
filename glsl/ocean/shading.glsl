// Ocean shading, spec/000 §1.2 (the thesis's OceanShader, from gasgiant/FFT-Ocean) with §1.7's
// reflection probe. Computes the linear radiance leaving the sea toward the camera: from above,
// Fresnel (Schlick 1994) between the sky's environment cubemap and the water body's upwelling
// light, the main light's glitter (sun by day, moon by night: one light, §1.2 change 2), foam
// and haze; from below, Snell's window; under water, the fog's extinction and colour.
// Failure cases guarded: grazing n·v and n·l (clamped before dividing), reflections below the
// horizon (folded up: the sea does not reflect itself), cubemap LODs past the map's last level,
// and total internal reflection beyond the critical angle (48.6°).

#include "math.glsl"
#include "fresnel.glsl"
// sea_plane.glsl: SEA_F0 = ((n − 1)/(n + 1))² and SeaBeckmann, shared with the skies' sea
#include "sea_plane.glsl"

uniform samplerCube uEnvironment;
uniform float uEnvironmentLods;      // mip levels of the cubemap − 1
uniform vec3 uMainLightDir;          // toward the light (sun or moon)
uniform vec3 uMainLightRadiance;
uniform float uSubgridMss;           // unresolved mean-square slope (CPU: Cox–Munk − resolved)

uniform bool uReflections; // @param true §1.7 reflect the sky's environment cubemap (the thesis's
                           // reflection probe); off: a flat sky colour
uniform vec3 uScatterColor; // @param (0.01, 0.045, 0.06) [0, 1] color §1.2 water body colour:
                            // upwelling radiance per unit of sky radiance
uniform float uSubsurface; // @param 1.0 [0, 5] step=0.05 §1.2 light through the wave crests, seen
                           // against the light
uniform vec3 uFoamColor;       // @param (0.9, 0.9, 0.9) [0, 1] color §1.2 foam albedo
uniform float uMssFloor; // @param 0.002 [0, 0.1] step=0.0005 smallest slope variance of the glitter
                         // lobe
uniform vec3 uUnderwaterColor; // @param (0.1, 0.55, 0.6) [0, 1] color §1.2 colour of the light
                               // scattered by the water, seen from inside
uniform float uUnderwaterClarity; // @param 0.5 [0.01, 1] step=0.01 §1.2 the thesis's underwater
                                  // clarity: 0 = murky (2 m visibility), 1 = clear (80 m)
uniform float uHazeDistance; // @param 12000 [100, 100000] step=100 unit=m distance over which the
                             // sea fades into the horizon colour

const float WATER_IOR = 1.333;
const vec3 FLAT_SKY = vec3(0.25, 0.3, 0.35);  // sky colour per unit of the light's green radiance
const float FLAT_SKY_MIN_LIGHT = 0.02;        // linear radiance: keeps the night's flat sky lit
const float MIN_MSS = 1e-5;                   // slope variance: the lobe never collapses to 0
const float MIN_COS = 1e-3;                   // cosines clamped before dividing by them
const float LOD_TEXELS = 128.0;  // texels per unit of RMS slope: rougher sea, blurrier reflection
const float UP_NUDGE = 1e-4;     // lifts the light's horizontal direction off 0 (sun at zenith)
const float BACKLIGHT_POWER = 4.0;   // narrowness of the light through the crests
const float HORIZON_RISE = 0.02;     // the horizon colour is read just above the horizon
const float HORIZON_LOD = 2.0;       // and blurred, at this mip level
const float MURKY_VISIBILITY = 2.0;  // m, clarity 0
const float CLEAR_VISIBILITY = 80.0; // m, clarity 1
const float CONTRAST_DEPTHS = 3.0;   // optical depths at the visibility: 5 % contrast (e^−3)
const vec3 EXTINCTION_TINT = vec3(4.0, 1.0, 0.8);  // red 4× faster than green, blue a bit slower
const float UNDERWATER_SCATTER = 0.1;  // share of the light from above the water scatters back

// Sky radiance (linear) toward unit direction dir, from the environment cubemap at mip level lod
// (clamped to [0, last level]). A direction below the horizon is mirrored up, so the sea never
// reflects itself. With uReflections off, a flat sky colour scaled by the light (the thesis's
// look without the probe), kept above a floor so that the night is not black.
vec3 EnvironmentRadiance(vec3 dir, float lod) {
    if (!uReflections) return FLAT_SKY * max(uMainLightRadiance.g, FLAT_SKY_MIN_LIGHT);
    dir.y = abs(dir.y);
    return textureLod(uEnvironment, dir, clamp(lod, 0.0, uEnvironmentLods)).rgb;
}

// The sky's light from straight up (the cubemap's last mip level): one value for every pixel.
// A program whose vertex stage reads it once (OCEAN_AMBIENT_VARYING: ocean/band.vert, which
// defines OCEAN_AMBIENT_SOURCE) passes it on flat; the others read the cubemap per pixel (on a
// software rasteriser, ~0.7 ms of the deferred pass at 640x360).
#if defined(OCEAN_AMBIENT_VARYING) && !defined(OCEAN_AMBIENT_SOURCE)
flat in vec3 vSkyAmbient;
vec3 OceanSkyAmbient() { return vSkyAmbient; }
#else
vec3 OceanSkyAmbient() { return EnvironmentRadiance(vec3(0.0, 1.0, 0.0), uEnvironmentLods); }
#endif

// Linear radiance leaving the sea surface toward the viewer, seen from above.
// p: surface point relative to the camera (m); n: unit normal; v: unit vector toward the camera;
// foam: coverage [0, 1]; lostMss: slope variance filtered out of this pixel's normal;
// crest: wave height in units of the sea's significant height (subsurface light).
// Reflection: Schlick's Fresnel with F0 = 0.0204 (n = 1.333) blends the water body's upwelling
// light and the cubemap, read at a LOD that grows with the RMS slope. Glitter: a Beckmann lobe
// whose slope variance is what the geometry cannot show (the floor, Cox–Munk 1954's unresolved
// remainder uSubgridMss from the CPU, and lostMss), so the highlight keeps its energy far away,
// with the Cook–Torrance shadowing term G. Foam is Lambertian; haze fades to the horizon
// colour over uHazeDistance.
// Failure cases: n·v and v·h clamped to MIN_COS before dividing; no glitter with the light
// below the horizon (step on l.y); a light straight overhead is nudged off the vertical before
// its horizontal direction is normalised.
vec3 OceanShadeAbove(vec3 p, vec3 n, vec3 v, float foam, float lostMss, float crest) {
    float mss = max(uMssFloor + uSubgridMss + lostMss, MIN_MSS);
    float nv = max(dot(n, v), MIN_COS);
    float F = SchlickFresnel(SEA_F0, nv);
    vec3 r = reflect(-v, n);
    float envLod = log2(max(sqrt(mss) * LOD_TEXELS, 1.0));
    vec3 reflected = EnvironmentRadiance(r, envLod);

    vec3 l = uMainLightDir;
    vec3 E = uMainLightRadiance;
    vec3 skyAmbient = OceanSkyAmbient();
    float nl = max(dot(n, l), 0.0);
    vec3 body = uScatterColor * (skyAmbient + E * max(l.y, 0.0) / PI);
    // light through thin crests, seen toward the light
    vec3 lightAcross = normalize(vec3(l.x, 0.0, l.z) + vec3(0.0, UP_NUDGE, 0.0));
    float back = pow(max(dot(v, -lightAcross), 0.0), BACKLIGHT_POWER);
    body += uScatterColor * E * uSubsurface * back * max(crest, 0.0);

    vec3 h = normalize(l + v);
    float nh = max(dot(n, h), 0.0);
    float G = min(1.0, min(2.0 * nh * nv / max(dot(v, h), MIN_COS),
                           2.0 * nh * nl / max(dot(v, h), MIN_COS)));
    vec3 spec = E * SchlickFresnel(SEA_F0, dot(v, h)) * SeaBeckmann(nh, mss) * G / (4.0 * nv)
              * step(0.0, l.y);

    vec3 water = mix(body, reflected, F) + spec;
    vec3 foamLit = uFoamColor * (skyAmbient + E * nl / PI);  // Lambert
    vec3 c = mix(water, foamLit, clamp(foam, 0.0, 1.0));

    float dist = length(p);
    vec3 horizon = EnvironmentRadiance(normalize(vec3(-v.x, HORIZON_RISE, -v.z)), HORIZON_LOD);
    return mix(c, horizon, 1.0 - exp(-dist / uHazeDistance));
}

// Linear radiance of the surface seen from below. n: the upward unit normal; v: unit vector
// pointing down toward the camera; transmitted: radiance above the surface along the refracted
// ray (the scene behind); waterLight: the water's own light in the reflected direction
// (in-scattered, from the fog). Snell's law gives the angle in air; Schlick's Fresnel is taken
// on the air side. Failure case: past the critical angle (48.6°) sin²θt ≥ 1 would give a NaN
// square root; it is total internal reflection, so only waterLight is returned.
vec3 OceanShadeBelow(vec3 n, vec3 v, vec3 transmitted, vec3 waterLight) {
    vec3 nd = -n;                                  // facing the camera, into the water
    float cosI = max(dot(v, nd), 0.0);             // angle in water
    float sinT2 = WATER_IOR * WATER_IOR * (1.0 - cosI * cosI);
    if (sinT2 >= 1.0) return waterLight;           // total internal reflection
    float cosT = sqrt(1.0 - sinT2);                // angle in air: Schlick on the air side
    float F = SchlickFresnel(SEA_F0, cosT);
    return mix(transmitted, waterLight, F);
}

// Extinction σ per channel under water (1/m), from the clarity [0, 1]: a visibility V from 2 m
// (murky) to 80 m (clear) at which green keeps 5 % of its contrast (σ = 3/V); red is absorbed
// 4× faster, blue a little slower. A clarity outside [0, 1] is clamped.
vec3 UnderwaterExtinction() {
    float visibility = mix(MURKY_VISIBILITY, CLEAR_VISIBILITY, clamp(uUnderwaterClarity, 0.0, 1.0));
    return CONTRAST_DEPTHS / visibility * EXTINCTION_TINT;
}

// Linear radiance the water scatters toward the eye (the fog colour): the sky and the main
// light from above, tinted by uUnderwaterColor. A light below the horizon adds nothing.
vec3 UnderwaterLight() {
    vec3 skyAmbient = OceanSkyAmbient();
    return uUnderwaterColor * UNDERWATER_SCATTER
         * (skyAmbient + uMainLightRadiance * max(uMainLightDir.y, 0.0) / PI);
}
