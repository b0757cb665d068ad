// =============================================================================================
// Procedural day–night sky — maritime thesis (spec/000 §1.7; its annex B: the shader
// properties of §B.1, then spec/000 eq. B.2, spec/000 eq. B.3 and spec/000 eq. B.4),
// "ProceduralSkybox", after Unity's legacy procedural skybox.
//
// Radiance toward direction p is the additive sum of four terms (spec/000 eq. B.4, fragment
// shader):
//   sun   = MiePhase(-f, f²) · SunIntensity · SunCol,  f = saturate(p·L_sun)^5
//                                                         (spec/000 eq. B.2, spec/000 eq. B.3)
//           MiePhase(c, c²) = 1.5 · (1 − G²)/(2 + G²) · (1 + c²) / max(t^(SunSize^0.65·10), 1e-4),
//           t = 1 + G² − 2G·c,  G = MIE_G = −0.99
//   halo  = smoothstep(0.5, 1.5, p·L_sun) · SunCol · ScatteringIntensity · scatInt,
//           scatInt = max(0.15, reversed smoothstep(0.6, 0.0, sin(sun elevation)))
//   sky   = gradient(elevation) from the keyframes around the hour (CPU: app/sim/daynight.py)
//   stars = saturate(star³ · 3) · StarIntensity,  star = StarTex(sphereUV · 2).r
//   moon  = (MoonTex(moonPos.xy + 0.5) · step(0.5, p·L_moon) · MoonIntensity
//            + smoothstep(0.97, 1.3, p·L_moon) · 0.8) · MoonCol,
//           moonPos = World2Moon·p·6, x mirrored
//
// Failure cases guarded here:
//  * the reversed smoothstep(0.6, 0.0, x) of the HLSL original is undefined in GLSL
//    → SmoothStepDown;
//  * the 1e-4 clamp keeps the sun finite at its centre (peak 400.7 × SunCol at the defaults);
//  * asin/atan2 arguments are clamped (a normalised vector can exceed 1 by rounding);
//  * beyond the thesis (switchable): the Earth hides sun, moon and stars below the horizon.
//
// Below the horizon the thesis shows the gradient clamped at the horizon colour (a flat band;
// uGround = 0, darkened by uBelowHorizon). Beyond the thesis, uGround = 1 draws a calm sea plane
// at y = 0 seen from uEyeHeight (the sky at sea level has no other ground):
//   sea  = mix(body, reflected, F) + glitter, then haze toward the horizon colour over distance
//   F    = Schlick 1994 Fresnel, F0 = 0.0204 (n = 1.333), at the incidence the waves leave,
//          cos = sqrt((n·v)² + mss) (facets tilted by the rms slope: a rough sea's horizon is
//          darker than the sky's); n = up
//   reflected = gradient + halo toward the mirrored direction at that incidence (no sun or
//          moon disk: the glitter is their reflection, spread by the waves)
//   body = uSeaColor · (sky ambient + E·max(l.y, 0)/π), sky ambient = the cosine-weighted mean
//          of the gradient over the upper hemisphere (uSkyAmbient, from the CPU); E = the main
//          light (sun by day, moon by night, already reddened by the air mass on the CPU)
//   glitter = E · F(v·h) · Beckmann(n·h, mss) · G / (4 n·v), mss = Cox & Munk 1954's slope
//          variance 0.003 + 0.00512·U for the wind U (CPU)
//   haze = 1 − exp(−(uEyeHeight / n·v) / 12 km), toward the horizon colour (gradient + halo)
// Failure cases of the sea: n·v and v·h clamped before division (the glitter stays finite at
// the horizon, where the haze and F → 1 meet the sky continuously); the horizontal direction of
// a ray straight down is kept non-zero before normalising.
// The sea's shared maths (reflection direction, Fresnel, Beckmann glitter, body, haze) is
// glsl/common/sea_plane.glsl, shared with the Preetham sky's sea.
// Twins for tests: app/sim/sky.py (mie_phase, sun_term, scattering_intensity_factor); the sea:
// app/sim/sea_plane.py. The sky ambient comes from app.sim.daynight.Keyframes.ambient_at.
// =============================================================================================
#include "math.glsl"
#include "sea_plane.glsl"

const float MIE_G = -0.990;
const float MIE_G2 = 0.9801;

uniform float uSunSize; // @param 0.05 [0, 1] step=0.005 §1.7 _SunSize: sun disk size (Mie exponent
                        // SunSize^0.65·10)
uniform float uSunIntensity; // @param 2 [0, 20] step=0.1 §1.7 _SunIntensity: sun disk brightness
uniform vec3 uSunColor; // @param (1, 1, 1) [0, 1] color §1.7 _SunCol: sun colour (also the main
                        // light's colour by day)
uniform float uScatteringIntensity; // @param 1 [0, 5] step=0.05 §1.7 _ScatteringIntensity: halo
                                    // strength around the sun
uniform float uStarIntensity; // @param 1 [0, 5] step=0.05 §1.7 _StarIntensity: star brightness
                              // (times the keyframes' star factor)
uniform vec3 uMoonColor; // @param (1, 1, 1) [0, 1] color §1.7 _MoonCol: moon colour (also the main
                         // light's colour by night)
uniform float uMoonIntensity; // @param 1.2 [1, 3] step=0.05 §1.7 _MoonIntensity: moon disk
                              // brightness
uniform bool uHorizonOcclusion; // @param true beyond the thesis: the Earth hides sun, moon and
                                // stars below the horizon
uniform float uBelowHorizon; // @param 1 [0, 1] step=0.01 beyond the thesis: brightness below the
                             // horizon (1 = the thesis's clamped horizon colour; sky.ground =
                             // horizon only)
uniform vec3 uSeaColor; // @param (0.01, 0.045, 0.06) [0, 1] color beyond the thesis: the sea
                        // plane's body colour, upwelling radiance per unit of irradiance/π
                        // (sky.ground = sea)
uniform float uSeaHaze; // @param 12000 [100, 100000] step=100 unit=m beyond the thesis: distance
                        // over which the sea plane fades into the horizon colour

uniform int uGround;                // 0 = the thesis's horizon colour, 1 = the sea (sky.ground)
uniform vec3 uMainLightDir;         // toward the main light (sun by day, moon by night)
uniform vec3 uMainLightRadiance;    // its colour × intensity
uniform vec3 uSkyAmbient;           // the gradient's cosine-weighted mean radiance over the upper
                                    // hemisphere (Keyframes.ambient_at, once per frame on the CPU)
uniform float uSeaMss;              // Cox–Munk slope variance of the sea plane's glitter
uniform float uSeaGlitter;          // 1; 0 in the cubemap without the sun
uniform float uEyeHeight;           // metres above the sea plane (≥ 0.5)

uniform vec3 uSunDir;        // unit vector toward the sun (the thesis's −_SunDirectionWS)
uniform vec3 uMoonDir;       // unit vector toward the moon
uniform mat3 uWorldToMoon;   // the thesis's (float3x3)_MoonWorld2Obj
uniform sampler2D uSkyGradient; // rows = keyframes, columns = elevation 0..1
uniform vec2 uGradientRows;     // texture v of the keyframes before and after the hour
uniform float uGradientMix;     // blend weight of the second keyframe
uniform float uKeyframeStars;   // keyframes' star visibility at this hour
uniform sampler2D uStarTex;
uniform sampler2D uMoonTex;
uniform float uGradientTexels;  // width of uSkyGradient

// spec/000 eq. B.2: Mie phase with the SunSize exponent; c = cos of the angle (with the sign
// flip of spec/000 eq. B.3).
float SkyMiePhase(float c, float c2) {
    float t = 1.0 + MIE_G2 - 2.0 * MIE_G * c;
    t = pow(max(t, 0.0), pow(uSunSize, 0.65) * 10.0);
    t = max(t, 1.0e-4);
    return 1.5 * ((1.0 - MIE_G2) / (2.0 + MIE_G2)) * (1.0 + c2) / t;
}

// spec/000 eq. B.3: calcSunAttenuation.
float SkySunAttenuation(vec3 p, vec3 towardSun) {
    float f = pow(saturate(dot(p, towardSun)), 5.0);
    return SkyMiePhase(-f, f * f);
}

vec3 SkyGradient(float elevationU) {
    float x = (clamp(elevationU, 0.0, 1.0) * (uGradientTexels - 1.0) + 0.5) / uGradientTexels;
    vec3 a = texture(uSkyGradient, vec2(x, uGradientRows.x)).rgb;
    vec3 b = texture(uSkyGradient, vec2(x, uGradientRows.y)).rgb;
    return mix(a, b, uGradientMix);
}

// spec/000 eq. B.4: the halo around the sun, strongest with the sun at the horizon.
vec3 SkyHalo(vec3 p) {
    float scatInt = max(0.15, SmoothStepDown(0.6, 0.0, uSunDir.y));
    return smoothstep(0.5, 1.5, dot(p, uSunDir)) * uSunColor * uScatteringIntensity * scatInt;
}

// Beyond the thesis: radiance of the calm sea plane toward p (p.y < 0); see the header and
// glsl/common/sea_plane.glsl (the maths every sky's sea shares).
vec3 SkySea(vec3 p) {
    float nvRough = SeaRoughIncidence(p, uSeaMss);
    vec3 r = SeaReflectionDirection(p, uSeaMss);
    vec3 reflected = SkyGradient(asin(nvRough) / HALF_PI) + SkyHalo(r);
    vec3 horizon = SkyGradient(0.0) + SkyHalo(SeaHorizonDirection(p));
    return SeaPlaneRadiance(p, reflected, horizon, uSkyAmbient, uMainLightDir, uMainLightRadiance,
                            uSeaColor, uSeaMss, uSeaGlitter, uEyeHeight, uSeaHaze);
}

// spec/000 eq. B.4: linear radiance of the sky toward unit direction p (world space, y up): the
// sum of sun, halo, gradient, stars and moon of the header, or the sea below the horizon.
vec3 SkyRadiance(vec3 p) {
    if (uGround == 1 && p.y < 0.0) return SkySea(p);
    vec2 sphereUV = vec2(atan(p.x, p.z) / TWO_PI, asin(ClampCosine(p.y)) / HALF_PI);
    float aboveHorizon = uHorizonOcclusion ? smoothstep(-0.01, 0.0, p.y) : 1.0;

    // Sun disk and horizon halo.
    vec3 sun = SkySunAttenuation(p, uSunDir) * uSunIntensity * uSunColor;
    sun += SkyHalo(p);

    vec3 sky = SkyGradient(sphereUV.y);

    float star = texture(uStarTex, sphereUV * 2.0).r;
    star = saturate(star * star * star * 3.0) * uStarIntensity * uKeyframeStars;

    vec3 moonPos = uWorldToMoon * p * 6.0;
    moonPos.x *= -1.0;
    float cosMoon = dot(p, uMoonDir);
    vec3 moonTex = texture(uMoonTex, moonPos.xy + 0.5).rgb * step(0.5, cosMoon);
    float moonScat = smoothstep(0.97, 1.3, cosMoon);
    vec3 moon = (moonTex * uMoonIntensity + moonScat * 0.8) * uMoonColor;

    sky *= mix(uBelowHorizon, 1.0, aboveHorizon);
    return sky + (sun + vec3(star) + moon) * aboveHorizon;
}
