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
//            + smoothstep(0.97, 1.3, p·L_moon) · 0.8) · MoonCol,  moonPos = World2Moon·p·6, x mirrored
//
// Failure cases guarded here:
//  * the reversed smoothstep(0.6, 0.0, x) of the HLSL original is undefined in GLSL → SmoothStepDown;
//  * the 1e-4 clamp keeps the sun finite at its centre (peak 400.7 × SunCol at the defaults);
//  * asin/atan2 arguments are clamped (a normalised vector can exceed 1 by rounding);
//  * beyond the thesis (switchable): the Earth hides sun, moon and stars below the horizon.
// Twin for tests: app/sim/sky.py (mie_phase, sun_term, halo_term).
// =============================================================================================
#include "math.glsl"

const float MIE_G = -0.990;
const float MIE_G2 = 0.9801;

uniform float uSunSize;             // @param 0.05 [0, 1] step=0.005 §1.7 _SunSize: sun disk size (Mie exponent SunSize^0.65·10)
uniform float uSunIntensity;        // @param 2 [0, 20] step=0.1 §1.7 _SunIntensity: sun disk brightness
uniform vec3 uSunColor;             // @param (1, 1, 1) [0, 1] color §1.7 _SunCol: sun colour (also the main light's colour by day)
uniform float uScatteringIntensity; // @param 1 [0, 5] step=0.05 §1.7 _ScatteringIntensity: halo strength around the sun
uniform float uStarIntensity;       // @param 1 [0, 5] step=0.05 §1.7 _StarIntensity: star brightness (times the keyframes' star factor)
uniform vec3 uMoonColor;            // @param (1, 1, 1) [0, 1] color §1.7 _MoonCol: moon colour (also the main light's colour by night)
uniform float uMoonIntensity;       // @param 1.2 [1, 3] step=0.05 §1.7 _MoonIntensity: moon disk brightness
uniform bool uHorizonOcclusion;     // @param true beyond the thesis: the Earth hides sun, moon and stars below the horizon
uniform float uBelowHorizon;        // @param 1 [0, 1] step=0.01 beyond the thesis: brightness below the horizon (1 = the thesis's clamped horizon colour)

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

// spec/000 eq. B.4: radiance of the sky toward unit direction p (world space, y up).
vec3 SkyRadiance(vec3 p) {
    vec2 sphereUV = vec2(atan(p.x, p.z) / TWO_PI, asin(ClampCosine(p.y)) / HALF_PI);
    float aboveHorizon = uHorizonOcclusion ? smoothstep(-0.01, 0.0, p.y) : 1.0;

    // Sun disk and horizon halo.
    vec3 sun = SkySunAttenuation(p, uSunDir) * uSunIntensity * uSunColor;
    float scatInt = max(0.15, SmoothStepDown(0.6, 0.0, uSunDir.y));
    sun += smoothstep(0.5, 1.5, dot(p, uSunDir)) * uSunColor * uScatteringIntensity * scatInt;

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
