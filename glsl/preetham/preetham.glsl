// =============================================================================================
// Preetham analytic daylight — cloud thesis (spec/001 §1.8: the sky behind the clouds
// is three.js Sky.js, "obtained from" Preetham, Shirley & Smits 1999, "A practical analytic
// model for daylight", SIGGRAPH'99). This file is the paper's own model (Preetham 1999 eq. 3,
// Preetham 1999 eq. 4 and its appendix A.2), not Sky.js's Rayleigh/Mie approximation.
//
// For a view direction at zenith angle θ and angle γ from the sun (sun zenith angle θs):
//   Preetham 1999 eq. 3:
//            F(θ, γ) = (1 + A·exp(B / cos θ)) · (1 + C·exp(D·γ) + E·cos²γ)       Perez et al.
//   Preetham 1999 eq. 4:
//            Y = Y_z · F(θ, γ) / F(0, θs), and likewise x, y with their own A..E
//   §A.2     A..E = slope·T + offset, T = turbidity (table of distribution coefficients)
//   §A.2     Y_z = (4.0453·T − 4.9710)·tan χ − 0.2155·T + 2.4192   [kcd/m²],
//            χ = (4/9 − T/120)·(π − 2θs)
//   §A.2     x_z = [T² T 1]·M_x·[θs³ θs² θs 1]ᵀ,  y_z = [T² T 1]·M_y·[θs³ θs² θs 1]ᵀ
//   xyY → XYZ: X = x/y·Y, Z = (1 − x − y)/y·Y;  XYZ → linear sRGB (D65 matrix)
//   §A.1     sun colour = exp(−0.008735·λ^−4.08·m) · exp(−β·λ^−1.3·m), β = 0.04608·T − 0.04586,
//            m = 1/(cos θs + 0.15·(93.885 − θs°)^−1.253), λ = 0.68/0.55/0.44 μm for R/G/B
//   output   = uExposure · twilight · (sky + sun disk)   (Y = 1 kcd/m² → 1.0 before exposure)
//            above the horizon; below it, see next.
//
// Below the horizon (uGround, preetham.ground): 0 = the paper's model clamped at the horizon
// (a flat band of the horizon colour: the model has no ground); 1 = beyond the paper and the
// thesis, a calm sea plane at y = 0 seen from uEyeHeight, the maths shared with the day–night
// sky in glsl/common/sea_plane.glsl (Schlick 1994's Fresnel at the incidence the waves leave,
// body lit by sky ambient and sun, Beckmann glitter for Cox & Munk 1954's slope variance,
// haze toward the horizon over uSeaHaze), with this sky supplying:
//   reflected = uExposure · twilight · sky(r)   (Preetham 1999 eq. 4, no sun disk: the glitter
//               is the sun's reflection), r = SeaReflectionDirection(p, mss)
//   horizon   = the same toward SeaHorizonDirection(p) (the clamped horizon colour)
//   ambient   = uSkyAmbient: (1/π)∫ L cosθ dω of that sky over the upper hemisphere, on the CPU
//               (app.sim.preetham.sky_ambient: 12 × 24 directions, recomputed only when the sun
//               or the turbidity change), not per pixel
//   E, l      = the frame's main light (uMainLightRadiance, uMainLightDir): the sun's
//               transmittance (§A.1) × preetham.sun_intensity × the horizon fade, the very
//               light the clouds are lit with under this sky, in the picture's units (at 59°
//               and T = 2.5 the sun's luminance ≈ 0.75 against a zenith of ≈ 0.40 and a sky
//               ambient of ≈ 0.43): the sea's glitter and body match the clouds, not the
//               disk's 200 kcd/m² (a drawn disk, far dimmer than the real sun).
//
// Failure cases and guards (the numpy twin app/sim/preetham.py does the same):
//  * below the horizon cos θ ≤ 0 makes exp(B / cos θ) blow up (B < 0 flips to +∞):
//    cos θ = max(cos θ, 1e-3), so the lower hemisphere shows the horizon colour (no ground)
//    unless the sea is drawn; the sea's reflection direction is always above the horizon
//    (cos θr ≥ √mss) and its own guards are in glsl/common/sea_plane.glsl;
//  * the model is undefined for the sun below the horizon (χ < 0, Y_z falls): θs is clamped
//    to 90° and the result fades with a twilight factor, smoothstep over elevation −6°…0°;
//  * turbidity outside [2, 10] can make Y_z or F(0, θs) ≤ 0: the parameter's range keeps T there;
//  * acos of a dot product of unit vectors is clamped (rounding can exceed 1);
//  * XYZ outside the sRGB gamut near the horizon gives small negative channels: clamped to 0.
// =============================================================================================
#include "math.glsl"
#include "sea_plane.glsl"

uniform float uTurbidity;      // @param 2.5 [2, 10] step=0.1 §1.8 turbidity T (2 = very clear, 10 = hazy)
uniform float uExposure;       // @param 0.05 [0.0001, 10] step=0.005 unit=1/(kcd/m²) linear radiance per kcd/m² of the model's luminance
uniform bool uSunDisk;         // @param true §1.8 draw the sun disk (the thesis shows the sun as a sphere)
uniform float uSunDiskRadius;  // @param 0.27 [0.05, 5] step=0.01 unit=° angular radius of the sun disk (the real sun: 0.27°)
uniform float uSunDiskIntensity; // @param 200 [0, 10000] step=1 unit=kcd/m² sun disk luminance above the atmosphere (times the sun's transmittance)
uniform vec3 uSunDir;          // unit vector toward the sun (world space, y up)
uniform vec3 uSeaColor;        // @param (0.01, 0.045, 0.06) [0, 1] color beyond the paper: the sea plane's body colour, upwelling radiance per unit of irradiance/π (preetham.ground = sea)
uniform float uSeaHaze;        // @param 12000 [100, 100000] step=100 unit=m beyond the paper: distance over which the sea plane fades into the horizon colour

uniform int uGround;             // 0 = the paper's clamped horizon colour, 1 = the sea (preetham.ground)
uniform vec3 uSkyAmbient;        // the sky's cosine-weighted mean radiance (CPU), exposure and twilight in
uniform vec3 uMainLightDir;      // toward the main light
uniform vec3 uMainLightRadiance; // its colour × intensity (what the clouds are lit with)
uniform float uSeaMss;           // Cox–Munk slope variance 0.003 + 0.00512·U (preetham.sea_wind)
uniform float uEyeHeight;        // metres above the sea plane (≥ 0.5)

const float PREETHAM_MIN_COS_THETA = 1.0e-3;
const float PREETHAM_TWILIGHT_DEGREES = 6.0;

struct PerezCoefficients { float A; float B; float C; float D; float E; };

// Preetham 1999 §A.2: distribution coefficients for luminance Y and chromaticities x, y.
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

// Preetham 1999 eq. 3: Perez et al. sky distribution F(θ, γ), with the below-horizon guard on
// cos θ.
float PreethamPerez(float cosTheta, float gamma, PerezCoefficients k) {
    float ct = max(cosTheta, PREETHAM_MIN_COS_THETA);
    float cg = cos(gamma);
    return (1.0 + k.A * exp(k.B / ct)) * (1.0 + k.C * exp(k.D * gamma) + k.E * cg * cg);
}

// Preetham 1999 §A.2: zenith luminance Y_z in kcd/m².
float PreethamZenithLuminance(float T, float thetaS) {
    float chi = (4.0 / 9.0 - T / 120.0) * (PI - 2.0 * thetaS);
    return (4.0453 * T - 4.9710) * tan(chi) - 0.2155 * T + 2.4192;
}

// Preetham 1999 §A.2: zenith chromaticity (x_z, y_z).
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

// The sun the model sees: zenith angle clamped to 90° (sun below the horizon → on it).
vec3 PreethamModelSun(vec3 sunDir, out float thetaS) {
    thetaS = acos(clamp(sunDir.y, 0.0, 1.0));
    float h = length(sunDir.xz);
    vec2 xz = h > 0.0 ? sunDir.xz / h * sin(thetaS) : vec2(0.0);
    return vec3(xz.x, cos(thetaS), xz.y);
}

// 1 with the sun above the horizon, smoothstep to 0 at 6° below it (civil twilight).
float PreethamTwilight(vec3 sunDir) {
    float elevationDeg = degrees(asin(ClampCosine(sunDir.y)));
    return smoothstep(-PREETHAM_TWILIGHT_DEGREES, 0.0, elevationDeg);
}

// Preetham 1999 eq. 4: (x, y, Y) toward unit direction dir for turbidity T.
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

vec3 PreethamxyYToXYZ(vec3 xyY) {
    return vec3(xyY.x / xyY.y * xyY.z, xyY.z, (1.0 - xyY.x - xyY.y) / xyY.y * xyY.z);
}

vec3 PreethamXYZToLinearSRGB(vec3 XYZ) {
    return vec3(dot(vec3(3.2404542, -1.5371385, -0.4985314), XYZ),
                dot(vec3(-0.9692660, 1.8760108, 0.0415560), XYZ),
                dot(vec3(0.0556434, -0.2040259, 1.0572252), XYZ));
}

// Linear sRGB of the sky in kcd/m² (no exposure, no twilight).
vec3 PreethamSkyRGB(vec3 dir, vec3 sunDir, float T) {
    return max(PreethamXYZToLinearSRGB(PreethamxyYToXYZ(PreethamSkyxyY(dir, sunDir, T))), vec3(0.0));
}

// Preetham 1999 §A.1: relative optical mass m(θs), finite at θs = 90° (≈ 36.5).
float PreethamAirMass(float thetaS) {
    return 1.0 / (cos(thetaS) + 0.15 * pow(93.885 - degrees(thetaS), -1.253));
}

// Preetham 1999 §A.1: sun colour through the atmosphere at λ = 680, 550, 440 nm (R, G, B):
// Rayleigh exp(−0.008735·λ^−4.08·m) times aerosols exp(−β·λ^−1.3·m), β = 0.04608·T − 0.04586.
vec3 PreethamSunTransmittance(float thetaS, float T) {
    const vec3 lambdaUm = vec3(0.680, 0.550, 0.440);
    float m = PreethamAirMass(thetaS);
    float beta = 0.04608 * T - 0.04586;
    return exp(-0.008735 * pow(lambdaUm, vec3(-4.08)) * m) * exp(-beta * pow(lambdaUm, vec3(-1.3)) * m);
}

float PreethamSunDiskCoverage(vec3 dir, vec3 sunDir, float radiusDeg) {
    float cIn = cos(radians(radiusDeg * 0.9));
    float cOut = cos(radians(radiusDeg * 1.1));
    float t = clamp((dot(dir, sunDir) - cOut) / (cIn - cOut), 0.0, 1.0);
    return t * t * (3.0 - 2.0 * t);
}

// The sky without the sun disk as the picture shows it: exposure · twilight · sky.
vec3 PreethamSkyNoDisk(vec3 dir) {
    return PreethamSkyRGB(dir, uSunDir, uTurbidity) * uExposure * PreethamTwilight(uSunDir);
}

// Beyond the paper: the calm sea plane toward p (p.y < 0); see the header.
vec3 PreethamSea(vec3 p) {
    vec3 reflected = PreethamSkyNoDisk(SeaReflectionDirection(p, uSeaMss));
    vec3 horizon = PreethamSkyNoDisk(SeaHorizonDirection(p));
    return SeaPlaneRadiance(p, reflected, horizon, uSkyAmbient, uMainLightDir, uMainLightRadiance,
                            uSeaColor, uSeaMss, 1.0, uEyeHeight, uSeaHaze);
}

// What the camera sees toward unit direction dir: exposure · twilight · (sky + disk), or the
// sea below the horizon.
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
