// =============================================================================================
// Cloud Model B — the maritime thesis's volumetric clouds (spec/000 §1.6; the thesis's annex
// code listings of "Clouds.shader", after Schneider, "The real-time volumetric cloudscapes of
// Horizon: Zero Dawn", SIGGRAPH'15). A box of cloud ray-marched at a fixed step.
//
// Equations (thesis numbers where it gives them, annex listings otherwise):
//   §A.4    rayBoxDistance: tmin = (boxMin − o)/d, tmax = (boxMax − o)/d, t1 = min, t2 = max,
//           dstA = max(t1.x, t1.y, t1.z), dstB = min(t2.x, t2.y, t2.z),
//           dstToBox = max(0, dstA), dstInsideBox = max(0, dstB − dstToBox)
//   §A.4, §A.5  sampleDensity(p):
//           samplePos = (halfSize + p)·CloudScale·0.001
//           edgeWeight = min(min(Fade, dist to x walls), min(Fade, dist to z walls)) / Fade
//           gradient = GradientNoise(planar xz uv of the box).r
//           gMin = remap(gradient, 0,1, 0.1,0.5), gMax = remap(gradient, 0,1, gMin,0.9)
//           heightGradient = sat(remap(h, 0,gMin, 0,1))·sat(remap(h, 1,gMax, 0,1))·edgeWeight
//           volumeFBM = dot(VolumeNoise(samplePos + CloudOffset·0.1), W_v/ΣW_v)·heightGradient
//           volumeDensity = volumeFBM + DensityThreshold·0.1
//           if volumeDensity > 0:  detailFBM = dot(DetailNoise(samplePos + CloudOffset·0.2).rgb, W_d/ΣW_d)
//              density = volumeDensity − (1 − detailFBM)·(1 − volumeFBM)³·DetailNoiseMultiplier·DensityMultiplier
//   spec/000 eq. 3.1  HG(cos θ, g) = (1 − g²) / (4π·(1 + g² − 2g·cos θ)^{3/2})
//   §A.3    phase(cos α) = P.z + P.w·(0.5·HG(cos α, P.x) + 0.5·HG(cos α, −P.y)),
//           P = (Forward Scattering, Back Scattering, Base Brightness, Phase Factor)
//   spec/000 eq. 3.2  Beer(d) = exp(−d);   spec/000 eq. 3.3  Powder(d) = 1 − exp(−2d)
//   §A.6    lightAtPos(p): march NumStepsLight midpoints from p to the box wall toward the sun,
//           T = exp(−τ·LightAbsortionSun), return DarknessThreshold + T·(1 − DarknessThreshold)
//   §A.7, §A.8  main march: E += ρ·step·T·lightAtPos·phase·Powder(ρ); T *= exp(−ρ·step·LightAbsortionCloud);
//           break when T < 0.01; output = background·T + E·SunColor
//
// Fixes against the thesis (spec/000 §1.6 and §4):
//  * light-direction double inversion: the thesis passes 1/L to rayBoxDistance, which divides
//    by its argument again, so the slab distances come out as (min − p)·L; it then clamps
//    |L.z| ≥ 0.085 (which leaves L.z = 0 at 0, sign(0) = 0). Here L itself is passed and no
//    clamp is applied. Components of |d| < 1e-20 are replaced by ±1e-20 before dividing (the
//    GLSL spec leaves x/0 unspecified; a 0/0 on a wall would be NaN), which gives ±huge finite
//    slab distances — the exact answer for a ray parallel to the slab. uThesisLightInversion
//    reproduces the thesis's code (with its clamp) for comparison charts and the stability test.
//  * the gradient uv's precedence slip (BoundsMin + BoundsMax·0.5) and xy/xz truncation: the
//    box's xz is mapped onto [0,1]² by (p.xz − boxMin.xz) / maxDim, the digest's stated intent;
//  * the coverage map drifts with the wind too (uCoverageShift, metres): the thesis moves only
//    the noise (_CloudOffset), so the cloud field — which the map shapes — would stay put;
//    GradientSimulator's own Offset "moves the noise" to move a storm front, which this does;
//  * the main loop has a step cap (uMaxSteps) so a huge box cannot hang the GPU;
//  * uWeatherCoverage (0 = the thesis): the coverage map also scales the base shape,
//    volumeFBM ·= mix(1, smoothstep(0.3, 0.7, gradient), uWeatherCoverage), so clear gaps and
//    cloud banks kilometres wide break the volume noise's repeating tile (Schneider's weather
//    map coverage; the map spans the whole box once, the noise tiles every 1/CloudScale km).
//  * the noise lookups' mip level: implicit derivatives inside the march loop (its break and
//    branches) are undefined in GLSL and would follow the neighbouring fragments' jitter and,
//    in an amortised march (app/render/amortise.py), rays a block of pixels apart; the level is
//    instead the one covering a pixel's footprint at the sample's distance, d · 2 tan(fov/2) / H
//    metres (gNoiseFootprint, set by the view march), the same for every way of marching;
// Failure cases left as the thesis has them: fixed-step banding (no jitter); powder takes the
// density, not the optical depth; a step larger than the cloud features skips them.
// Numpy twins: app/sim/clouds_b.py.
// =============================================================================================
#include "math.glsl"
#include "phase.glsl"
#include "intersect.glsl"

uniform vec3 uBoundsMin;               // @param (-1500, 1000, -1500) [-100000, 100000] step=10 unit=m §1.6 _BoundsMin: cloud container, lower corner
uniform vec3 uBoundsMax;               // @param (1500, 1400, 1500) [-100000, 100000] step=10 unit=m §1.6 _BoundsMax: cloud container, upper corner
uniform float uCloudScale;             // @param 0.6 [0.01, 20] step=0.01 §1.6 Cloud Scale: noise tiles per km (samplePos = (halfSize + p)·scale·0.001)
uniform float uDensityThreshold;       // @param -5 [-100, 10] step=0.05 §1.6 Density Threshold: added ×0.1 to the base shape (negative thins the clouds)
uniform float uDensityMultiplier;      // @param 1 [0, 10] step=0.05 §1.6 Density Multiplier: weight of the detail erosion (listing A.5, line 26)
uniform float uDetailNoiseMultiplier;  // @param 0.5 [0, 10] step=0.05 §1.6 _DetailNoiseMultiplier: strength of the detail noise
uniform float uContainerEdgeFadeDst;   // @param 200 [0.001, 100000] step=10 unit=m §1.6 Container Edge Fade: distance from the x/z walls over which density fades in
uniform vec4 uVolumeNoiseWeight;       // @param (1, 0.48, 0.15, 0) [0, 10] step=0.01 §1.6 Volume Noise Weights: weight of each channel of the volume noise
uniform vec3 uDetailNoiseWeight;       // @param (1, 0.5, 0.25) [0, 10] step=0.01 §1.6 Detail Noise Weights: weight of each channel of the detail noise
uniform int uNumStepsLight;            // @param 8 [1, 64] §1.6 Num Steps Lightning: light-march steps toward the sun
uniform float uFixedStepSize;          // @param 20 [0.5, 1000] step=0.5 unit=m §1.6 Fixed Step Modeling: primary step size
uniform int uMaxSteps;                 // @param 512 [1, 8192] beyond the thesis: cap on primary steps per pixel
uniform float uLightAbsortionSun;      // @param 0.03 [0, 10] step=0.001 unit=1/m §1.6 Light Absortion Sun: extinction along the light march (lightAtPos)
uniform float uLightAbsortionCloud;    // @param 0.02 [0, 10] step=0.001 unit=1/m §1.6 Light Absortion (Cloud): extinction along the view ray
uniform float uDarknessThreshold;      // @param 0.2 [0, 1] step=0.01 §1.6 Darkness Threshold: floor of lightAtPos on the dark side
uniform float uForwardScattering;      // @param 0.83 [-0.99, 0.99] step=0.01 §1.6 Forward Scattering: g of the forward HG lobe (_PhaseParams.x)
uniform float uBackScattering;         // @param 0.3 [-0.99, 0.99] step=0.01 §1.6 Back Scattering: the back lobe uses g = −this (_PhaseParams.y)
uniform float uBaseBrightness;         // @param 0.8 [0, 10] step=0.01 §1.6 Bare Brightness: additive base of the phase (_PhaseParams.z)
uniform float uPhaseFactor;            // @param 0.15 [0, 10] step=0.01 §1.6 Phase Factor: weight of the blended HG lobes (_PhaseParams.w)
uniform bool uThesisLightInversion;    // @param false beyond the thesis: reproduce the thesis's double inversion and 0.085 clamp (for comparison only)
uniform float uWeatherCoverage;        // @param 0 [0, 1] step=0.01 §1.6 beyond the thesis: how far GradientSimulator's map also thins the clouds where it is low (a weather map's coverage; 0 = the thesis, the map shapes the height band only)

uniform vec3 uCloudOffset;    // _CloudOffset: wind offset in noise units (set by the effect from wind × time)
uniform vec2 uCoverageShift;  // metres the coverage map has drifted along x, z (wind × time; beyond the thesis)
uniform sampler3D uVolumeNoise;   // shape ("volume") noise, RGBA
uniform sampler3D uDetailNoise;   // detail noise, RGB (+ A = 1)
uniform sampler2D uGradientNoise; // GradientSimulator's 2D coverage map, R used

// One pixel's footprint at the sample being taken, in noise units (samplePos): the noise
// lookups read the mip level that covers it. The view march sets it for each view sample (the
// light march from there inherits it); 0 reads the base level.
float gNoiseFootprint = 0.0;

float CloudsBNoiseLod(sampler3D noise) {
    return log2(max(gNoiseFootprint * float(textureSize(noise, 0).x), 1.0e-8));
}


// spec/000 §A.4, distances along d to the box and through it: (dstToBox, dstInsideBox). d need
// not be unit length (distances are in units of |d|); a zero component is allowed.
vec2 CloudsBRayBoxDistance(vec3 boundsMin, vec3 boundsMax, vec3 origin, vec3 dir) {
    vec2 t = RayBoxIntersect(origin, dir, boundsMin, boundsMax);
    float dstToBox = max(0.0, t.x);
    return vec2(dstToBox, max(0.0, t.y - dstToBox));
}

// The thesis's rayBoxDistance as it is called from lightAtPos: it receives 1/L and divides by it
// (the double inversion) — the slab distances are (min − p)·L. Comparison only.
vec2 CloudsBRayBoxDistanceThesis(vec3 boundsMin, vec3 boundsMax, vec3 origin, vec3 invDirArgument) {
    vec3 t0 = (boundsMin - origin) / invDirArgument;
    vec3 t1 = (boundsMax - origin) / invDirArgument;
    vec3 tmin = min(t0, t1);
    vec3 tmax = max(t0, t1);
    float dstA = max(max(tmin.x, tmin.y), tmin.z);
    float dstB = min(tmax.x, min(tmax.y, tmax.z));
    float dstToBox = max(0.0, dstA);
    return vec2(dstToBox, max(0.0, dstB - dstToBox));
}

// spec/000 §A.3: two lobes blended 50/50, scaled by the phase factor, on the base brightness.
float CloudsBPhase(float cosAlpha) {
    float blend = 0.5;
    float hg = HenyeyGreenstein(cosAlpha, uForwardScattering) * (1.0 - blend)  // spec/000 eq. 3.1
             + HenyeyGreenstein(cosAlpha, -uBackScattering) * blend;
    return uBaseBrightness + hg * uPhaseFactor;
}

float CloudsBBeer(float d) { return exp(-d); }                 // spec/000 eq. 3.2
float CloudsBPowder(float d) { return 1.0 - exp(-2.0 * d); }   // spec/000 eq. 3.3

float CloudsBRemap(float v, float a, float b, float c, float d) {
    return c + (v - a) * (d - c) / (b - a);
}

// Edge fade toward the x/z walls: 0 on a wall, 1 from Fade inside.
float CloudsBEdgeWeight(vec3 p) {
    float edgeX = min(uContainerEdgeFadeDst, min(p.x - uBoundsMin.x, uBoundsMax.x - p.x));
    float edgeZ = min(uContainerEdgeFadeDst, min(p.z - uBoundsMin.z, uBoundsMax.z - p.z));
    return max(min(edgeX, edgeZ), 0.0) / uContainerEdgeFadeDst;
}

// Height band from the coverage value: 0 at h = 0 and h = 1, 1 between gMin and gMax.
float CloudsBHeightGradient(float heightPercent, float gradient) {
    float gMin = CloudsBRemap(gradient, 0.0, 1.0, 0.1, 0.5);
    float gMax = CloudsBRemap(gradient, 0.0, 1.0, gMin, 0.9);
    return saturate(CloudsBRemap(heightPercent, 0.0, gMin, 0.0, 1.0))
         * saturate(CloudsBRemap(heightPercent, 1.0, gMax, 0.0, 1.0));
}

// The coverage value of GradientNoise over the box's xz (fixed planar mapping, see header).
float CloudsBCoverage(vec3 p) {
    vec3 size = uBoundsMax - uBoundsMin;
    float maxDim = max(size.x, size.z);
    vec2 uv = (p.xz - uBoundsMin.xz - uCoverageShift) / maxDim;
    float texels = gNoiseFootprint / (uCloudScale * 0.001) / maxDim * float(textureSize(uGradientNoise, 0).x);
    return textureLod(uGradientNoise, uv, log2(max(texels, 1.0e-8))).r;
}

// The weather map's coverage factor on the base shape (1 with uWeatherCoverage = 0, the thesis).
float CloudsBWeatherCover(float gradient) {
    return mix(1.0, smoothstep(0.3, 0.7, gradient), uWeatherCoverage);
}

// spec/000 §A.4, §A.5: sampleDensity.
float CloudsBSampleDensity(vec3 p) {
    vec3 size = uBoundsMax - uBoundsMin;
    vec3 halfSize = size * 0.5;
    vec3 samplePos = (halfSize + p) * uCloudScale * 0.001;
    float heightPercent = (p.y - uBoundsMin.y) / size.y;
    float gradient = CloudsBCoverage(p);
    float heightGradient = CloudsBHeightGradient(heightPercent, gradient) * CloudsBEdgeWeight(p)
                         * CloudsBWeatherCover(gradient);

    vec4 vn = textureLod(uVolumeNoise, samplePos + uCloudOffset * 0.1, CloudsBNoiseLod(uVolumeNoise));
    vec4 wv = uVolumeNoiseWeight / max(dot(uVolumeNoiseWeight, vec4(1.0)), 1.0e-6);
    float volumeFBM = dot(vn, wv) * heightGradient;
    float volumeDensity = volumeFBM + uDensityThreshold * 0.1;
    if (volumeDensity > 0.0) {
        vec3 dn = textureLod(uDetailNoise, samplePos + uCloudOffset * 0.2, CloudsBNoiseLod(uDetailNoise)).rgb;
        vec3 wd = uDetailNoiseWeight / max(dot(uDetailNoiseWeight, vec3(1.0)), 1.0e-6);
        float detailFBM = dot(dn, wd);
        float oneMinusShape = 1.0 - volumeFBM;
        float erode = oneMinusShape * oneMinusShape * oneMinusShape;
        float detailDensity = (1.0 - detailFBM) * erode * uDetailNoiseMultiplier;
        return volumeDensity - detailDensity * uDensityMultiplier;
    }
    return 0.0;
}

// spec/000 §A.6, lightAtPos: transmittance toward the sun from p, floored at the darkness threshold.
// towardSun: unit vector from the scene toward the sun (the thesis's L = −_SunDir).
float CloudsBLightAtPos(vec3 p, vec3 towardSun) {
    float dIn;
    if (uThesisLightInversion) {
        vec3 L = towardSun;
        if (abs(L.z) < 0.085) L.z = sign(L.z) * 0.085;
        dIn = CloudsBRayBoxDistanceThesis(uBoundsMin, uBoundsMax, p, 1.0 / L).y;
    } else {
        dIn = CloudsBRayBoxDistance(uBoundsMin, uBoundsMax, p, towardSun).y;
    }
    float stepSize = dIn / float(uNumStepsLight);
    p += towardSun * stepSize * 0.5;
    float totalDensity = 0.0;
    for (int i = 0; i < uNumStepsLight; i++) {
        totalDensity += max(0.0, CloudsBSampleDensity(p) * stepSize);
        p += towardSun * stepSize;
    }
    float transmittance = CloudsBBeer(totalDensity * uLightAbsortionSun);
    return uDarknessThreshold + transmittance * (1.0 - uDarknessThreshold);
}
