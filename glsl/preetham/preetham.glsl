// Preetham analytic daylight for the cloud thesis (spec/001 §1.8: its sky is three.js Sky.js,
// "obtained from" Preetham, Shirley & Smits 1999, "A practical analytic model for daylight").
// This file is the paper's own model (Preetham 1999 eq. 3, Preetham 1999 eq. 4, appendix A),
// not Sky.js's Rayleigh/Mie approximation: the sky's linear radiance toward a direction, its
// sun disk, and (beyond the paper, preetham.ground = sea) a calm sea plane below the horizon.
// Output is uExposure · twilight · (sky + sun disk); Y = 1 kcd/m² gives 1.0 before exposure.
// Failure cases guarded (the numpy twin app/sim/preetham.py does the same): below the horizon
// (cos θ floored), the sun below the horizon (θs clamped to 90°, twilight fade), acos of rounded
// dot products (clamped), XYZ outside the sRGB gamut (negatives clamped to 0). Turbidity outside
// [2, 10] can make Y_z or F(0, θs) ≤ 0: the parameter's range keeps T inside.
#include "math.glsl"
#include "sea_plane.glsl"

uniform float uTurbidity; // @param 2.5 [2, 10] step=0.1 §1.8 turbidity T (2 = very clear, 10 =
                          // hazy)
uniform float uExposure; // @param 0.05 [0.0001, 10] step=0.005 unit=1/(kcd/m²) linear radiance per
                         // kcd/m² of the model's luminance
uniform bool uSunDisk; // @param true §1.8 draw the sun disk (the thesis shows the sun as a sphere)
uniform float uSunDiskRadius; // @param 0.27 [0.05, 5] step=0.01 unit=° angular radius of the sun
                              // disk (the real sun: 0.27°)
uniform float uSunDiskIntensity; // @param 200 [0, 10000] step=1 unit=kcd/m² sun disk luminance
                                 // above the atmosphere (times the sun's transmittance)
uniform vec3 uSunDir;          // unit vector toward the sun (world space, y up)
uniform vec3 uSeaColor; // @param (0.01, 0.045, 0.06) [0, 1] color beyond the paper: the sea plane's
                        // body colour, upwelling radiance per unit of irradiance/π (preetham.ground
                        // = sea)
uniform float uSeaHaze; // @param 12000 [100, 100000] step=100 unit=m beyond the paper: distance
                        // over which the sea plane fades into the horizon colour

uniform int uGround;             // preetham.ground: 0 the clamped horizon colour, 1 the sea
uniform vec3 uSkyAmbient;        // the sky's cosine-weighted mean radiance (CPU), with exposure and
                                 // twilight
uniform vec3 uMainLightDir;      // toward the main light
uniform vec3 uMainLightRadiance; // its colour × intensity (what the clouds are lit with)
uniform float uSeaMss;           // Cox–Munk slope variance 0.003 + 0.00512·U (preetham.sea_wind)
uniform float uEyeHeight;        // metres above the sea plane (≥ 0.5)

const float PREETHAM_MIN_COS_THETA = 1.0e-3;  // floor of cos θ: exp(B / cos θ) blows up below
const float PREETHAM_TWILIGHT_DEGREES = 6.0;  // °: civil twilight, the sky fades to 0 over it
// Kasten's relative optical mass, as Preetham 1999 §A.1 gives it
const float PREETHAM_AIR_MASS_K = 0.15;
const float PREETHAM_AIR_MASS_ANGLE = 93.885;   // °
const float PREETHAM_AIR_MASS_EXPONENT = -1.253;
// Preetham 1999 §A.1's sun transmittance: Rayleigh k·λ^−4.08, aerosols β·λ^−1.3 (λ in μm)
const float PREETHAM_RAYLEIGH_K = 0.008735;
const float PREETHAM_RAYLEIGH_EXPONENT = -4.08;
const float PREETHAM_AEROSOL_EXPONENT = -1.3;
const float PREETHAM_DISK_INNER = 0.9;  // fraction of the disk's radius: full coverage inside
const float PREETHAM_DISK_OUTER = 1.1;  // fraction of the disk's radius: none outside

struct PerezCoefficients { float A; float B; float C; float D; float E; };

// Preetham 1999 §A.2: the Perez distribution coefficients A..E = slope · T + offset for
// luminance Y (and, below, the chromaticities x and y), T the turbidity (dimensionless, [2, 10]).
PerezCoefficients PreethamCoefficientsY(float T) {
    return PerezCoefficients(0.1787 * T - 1.4630, -0.3554 * T + 0.4275, -0.0227 * T + 5.3251,
                             0.1206 * T - 2.5771, -0.0670 * T + 0.3703);
}
PerezCoefficients PreethamCoefficientsX(float T) {
    return PerezCoefficients(-0.0193 * T - 0.2592, -0.0665 * T + 0.0008, -0.0004 * T + 0.2125,
                             -0.0641 * T - 0.8989, -0.0033 * T + 0.0452);
}
PerezCoefficients PreethamCoefficientsYChroma(float T) {
    return PerezCoefficients(-0.0167 * T - 0.2608, -0.0950 * T + 0.0092, -0.0079 * T + 0.2102,
                             -0.0441 * T - 1.6537, -0.0109 * T + 0.0529);
}

// Preetham 1999 eq. 3: the Perez et al. sky distribution
// F(θ, γ) = (1 + A·exp(B / cos θ)) · (1 + C·exp(D·γ) + E·cos²γ), θ the view's zenith angle, γ
// (radians) its angle from the sun; dimensionless. Below the horizon cos θ ≤ 0 makes exp(B/cos θ)
// blow up (B < 0 flips to +∞): cos θ is floored at PREETHAM_MIN_COS_THETA, so the lower
// hemisphere shows the horizon's colour (the model has no ground).
float PreethamPerez(float cosTheta, float gamma, PerezCoefficients k) {
    float ct = max(cosTheta, PREETHAM_MIN_COS_THETA);
    float cg = cos(gamma);
    return (1.0 + k.A * exp(k.B / ct)) * (1.0 + k.C * exp(k.D * gamma) + k.E * cg * cg);
}

// Preetham 1999 §A.2: zenith luminance Y_z = (4.0453 T − 4.9710) tan χ − 0.2155 T + 2.4192 in
// kcd/m², χ = (4/9 − T/120)(π − 2θs), θs the sun's zenith angle (radians, ≤ π/2: with the sun
// below the horizon χ < 0 and Y_z falls, so callers clamp θs).
float PreethamZenithLuminance(float T, float thetaS) {
    float chi = (4.0 / 9.0 - T / 120.0) * (PI - 2.0 * thetaS);
    return (4.0453 * T - 4.9710) * tan(chi) - 0.2155 * T + 2.4192;
}

// Preetham 1999 §A.2: zenith chromaticity (x_z, y_z) = [T² T 1] · M · [θs³ θs² θs 1]ᵀ with
// the paper's matrices M_x and M_y, θs in radians.
vec2 PreethamZenithChromaticity(float T, float thetaS) {
    vec3 t = vec3(T * T, T, 1.0);
    vec4 th = vec4(thetaS * thetaS * thetaS, thetaS * thetaS, thetaS, 1.0);
    // rows T², T, 1 of M_x and M_y, as columns of a mat3x4 product written out
    vec4 mx = t.x * vec4(0.00166, -0.00375, 0.00209, 0.0)
            + t.y * vec4(-0.02903, 0.06377, -0.03202, 0.00394)
            + t.z * vec4(0.11693, -0.21196, 0.06052, 0.25886);
    vec4 my = t.x * vec4(0.00275, -0.00610, 0.00317, 0.0)
            + t.y * vec4(-0.04214, 0.08970, -0.04153, 0.00516)
            + t.z * vec4(0.15346, -0.26756, 0.06670, 0.26688);
    return vec2(dot(mx, th), dot(my, th));
}

// The sun the model sees, a unit vector: its zenith angle θs (radians, out) clamped to 90°, so a
// sun below the horizon sits on it (the model is undefined there); a sun at the zenith keeps
// xz = 0.
vec3 PreethamModelSun(vec3 sunDir, out float thetaS) {
    thetaS = acos(clamp(sunDir.y, 0.0, 1.0));
    float h = length(sunDir.xz);
    vec2 xz = h > 0.0 ? sunDir.xz / h * sin(thetaS) : vec2(0.0);
    return vec3(xz.x, cos(thetaS), xz.y);
}

// Twilight factor in [0, 1]: 1 with the sun above the horizon, a smoothstep to 0 at
// PREETHAM_TWILIGHT_DEGREES below it. Beyond the paper: it fades the clamped model at night.
float PreethamTwilight(vec3 sunDir) {
    float elevationDeg = degrees(asin(ClampCosine(sunDir.y)));
    return smoothstep(-PREETHAM_TWILIGHT_DEGREES, 0.0, elevationDeg);
}

// Preetham 1999 eq. 4: (x, y, Y) toward the unit direction dir for turbidity T, each the zenith
// value times F(θ, γ) / F(0, θs) with its own coefficients; Y in kcd/m². acos of the rounded
// dot product is clamped.
vec3 PreethamSkyxyY(vec3 dir, vec3 sunDir, float T) {
    float thetaS;
    vec3 s = PreethamModelSun(sunDir, thetaS);
    float gamma = acos(ClampCosine(dot(dir, s)));
    float cosTheta = dir.y;
    PerezCoefficients kY = PreethamCoefficientsY(T);
    PerezCoefficients kx = PreethamCoefficientsX(T);
    PerezCoefficients ky = PreethamCoefficientsYChroma(T);
    vec2 xyZenith = PreethamZenithChromaticity(T, thetaS);
    float Yz = PreethamZenithLuminance(T, thetaS);
    float x = xyZenith.x * PreethamPerez(cosTheta, gamma, kx) / PreethamPerez(1.0, thetaS, kx);
    float y = xyZenith.y * PreethamPerez(cosTheta, gamma, ky) / PreethamPerez(1.0, thetaS, ky);
    float Y = Yz * PreethamPerez(cosTheta, gamma, kY) / PreethamPerez(1.0, thetaS, kY);
    return vec3(x, y, Y);
}

// CIE xyY → XYZ: X = x/y·Y, Z = (1 − x − y)/y·Y.
vec3 PreethamxyYToXYZ(vec3 xyY) {
    return vec3(xyY.x / xyY.y * xyY.z, xyY.z, (1.0 - xyY.x - xyY.y) / xyY.y * xyY.z);
}

// CIE XYZ → linear sRGB (the D65 matrix); colours out of gamut give negative channels.
vec3 PreethamXYZToLinearSRGB(vec3 XYZ) {
    return vec3(dot(vec3(3.2404542, -1.5371385, -0.4985314), XYZ),
                dot(vec3(-0.9692660, 1.8760108, 0.0415560), XYZ),
                dot(vec3(0.0556434, -0.2040259, 1.0572252), XYZ));
}

// Linear sRGB of the sky in kcd/m² (no exposure, no twilight). Out-of-gamut XYZ near the
// horizon gives small negative channels: clamped to 0.
vec3 PreethamSkyRGB(vec3 dir, vec3 sunDir, float T) {
    return max(PreethamXYZToLinearSRGB(PreethamxyYToXYZ(PreethamSkyxyY(dir, sunDir, T))),
               vec3(0.0));
}

// Preetham 1999 §A.1: relative optical mass m = 1/(cos θs + 0.15 (93.885 − θs°)^−1.253),
// dimensionless, θs in radians; finite at θs = 90° (≈ 36.5), where 1/cos θs would not be.
float PreethamAirMass(float thetaS) {
    return 1.0 / (cos(thetaS) + PREETHAM_AIR_MASS_K
                  * pow(PREETHAM_AIR_MASS_ANGLE - degrees(thetaS), PREETHAM_AIR_MASS_EXPONENT));
}

// Preetham 1999 §A.1: the sun's transmittance through the atmosphere ([0, 1], rgb) at λ = 680,
// 550, 440 nm (R, G, B): Rayleigh exp(−0.008735·λ^−4.08·m) times aerosols exp(−β·λ^−1.3·m),
// β = 0.04608·T − 0.04586, m = PreethamAirMass(θs), θs in radians.
vec3 PreethamSunTransmittance(float thetaS, float T) {
    const vec3 lambdaUm = vec3(0.680, 0.550, 0.440);
    float m = PreethamAirMass(thetaS);
    float beta = 0.04608 * T - 0.04586;
    return exp(-PREETHAM_RAYLEIGH_K * pow(lambdaUm, vec3(PREETHAM_RAYLEIGH_EXPONENT)) * m)
         * exp(-beta * pow(lambdaUm, vec3(PREETHAM_AEROSOL_EXPONENT)) * m);
}

// The sun disk's coverage ([0, 1]) of the unit direction dir: 1 within 0.9 of its angular
// radius (degrees), 0 beyond 1.1 of it, a smoothstep between (an antialiased edge).
float PreethamSunDiskCoverage(vec3 dir, vec3 sunDir, float radiusDeg) {
    float cIn = cos(radians(radiusDeg * PREETHAM_DISK_INNER));
    float cOut = cos(radians(radiusDeg * PREETHAM_DISK_OUTER));
    float t = clamp((dot(dir, sunDir) - cOut) / (cIn - cOut), 0.0, 1.0);
    return t * t * (3.0 - 2.0 * t);
}

// The sky without the sun disk as the picture shows it: exposure · twilight · sky.
vec3 PreethamSkyNoDisk(vec3 dir) {
    return PreethamSkyRGB(dir, uSunDir, uTurbidity) * uExposure * PreethamTwilight(uSunDir);
}

// Beyond the paper and the thesis (uGround = 1): the calm sea plane at y = 0 seen from
// uEyeHeight (m) toward p (p.y < 0), linear radiance. The maths is glsl/common/sea_plane.glsl's,
// shared with the day–night sky (Schlick 1994's Fresnel at the incidence the waves leave, the
// body lit by sky ambient and sun, Beckmann glitter for Cox & Munk 1954's slope variance uSeaMss,
// haze toward the horizon over uSeaHaze); this sky supplies:
//   reflected  exposure · twilight · sky(r) (Preetham 1999 eq. 4, no sun disk: the glitter is
//              the sun's reflection), r = SeaReflectionDirection(p, mss), always above the
//              horizon (cos θr ≥ √mss); sea_plane.glsl guards the rest;
//   horizon    the same toward SeaHorizonDirection(p) (the clamped horizon colour);
//   ambient    uSkyAmbient, (1/π)∫ L cosθ dω of this sky over the upper hemisphere, on the CPU
//              (app.sim.preetham.sky_ambient: 12 × 24 directions, recomputed only when the sun or
//              the turbidity change);
//   E, l       the frame's main light (uMainLightRadiance, uMainLightDir): the sun's
//              transmittance (§A.1) × preetham.sun_intensity × the horizon fade, the light the
//              clouds are lit with, in the picture's units (at 59° and T = 2.5 the sun's
//              luminance ≈ 0.75 against a zenith of ≈ 0.40 and an ambient of ≈ 0.43): the sea
//              matches the clouds, not the disk's 200 kcd/m² (a drawn disk, far dimmer than the
//              real sun).
vec3 PreethamSea(vec3 p) {
    vec3 reflected = PreethamSkyNoDisk(SeaReflectionDirection(p, uSeaMss));
    vec3 horizon = PreethamSkyNoDisk(SeaHorizonDirection(p));
    return SeaPlaneRadiance(p, reflected, horizon, uSkyAmbient, uMainLightDir, uMainLightRadiance,
                            uSeaColor, uSeaMss, 1.0, uEyeHeight, uSeaHaze);
}

// What the camera sees toward the unit direction dir, linear radiance:
// uExposure · twilight · (sky + disk) above the horizon; below it (uGround, preetham.ground) the
// paper's model clamped at the horizon (0: a flat band of the horizon's colour) or the sea (1).
vec3 PreethamSkyRadiance(vec3 dir) {
    if (uGround == 1 && dir.y < 0.0) return PreethamSea(dir);
    vec3 rgb = PreethamSkyRGB(dir, uSunDir, uTurbidity);
    if (uSunDisk && dir.y >= 0.0) {
        float thetaS;
        PreethamModelSun(uSunDir, thetaS);
        rgb += PreethamSunDiskCoverage(dir, uSunDir, uSunDiskRadius) * uSunDiskIntensity
             * PreethamSunTransmittance(thetaS, uTurbidity);
    }
    return rgb * uExposure * PreethamTwilight(uSunDir);
}
