// Cloud model B: the maritime thesis's volumetric clouds (spec/000 §1.6 and the annex listings
// of its "Clouds.shader", §A.3–§A.8, after Schneider 2015, the clouds of Horizon: Zero Dawn):
// a box of cloud marched at a fixed step by clouds_b.frag. This file holds the model: the
// density field, the phase, Beer and powder, and the light march, each function with its
// listing or equation, units and failure case. Numpy twins: app/sim/clouds_b.py.
// Fixes against the thesis (§1.6, §4), each at its function: the light direction's double
// inversion, the coverage map's uv, the map's drift with the wind, the march's step cap
// (uMaxSteps), the weather coverage switch and the noise lookups' mip level.
// Failure cases left as the thesis has them: fixed-step banding (no jitter); powder takes the
// density, not the optical depth; a step larger than the cloud's features skips them.
#include "math.glsl"
#include "phase.glsl"
#include "intersect.glsl"

uniform vec3 uBoundsMin;               // @param (-1500, 1000, -1500) [-100000, 100000] step=10
                                       //   unit=m §1.6 _BoundsMin: cloud container, lower corner
uniform vec3 uBoundsMax;               // @param (1500, 1400, 1500) [-100000, 100000] step=10 unit=m
                                       //   §1.6 _BoundsMax: cloud container, upper corner
uniform float uCloudScale;             // @param 0.6 [0.01, 20] step=0.01 §1.6 Cloud Scale: noise
                                       //   tiles per km (samplePos = (halfSize + p)·scale·0.001)
uniform float uDensityThreshold;       // @param -5 [-100, 10] step=0.05 §1.6 Density Threshold:
                                       //   added ×0.1 to the base shape (negative thins the clouds)
uniform float uDensityMultiplier;      // @param 1 [0, 10] step=0.05 §1.6 Density Multiplier: weight
                                       //   of the detail erosion (listing A.5, line 26)
uniform float uDetailNoiseMultiplier;  // @param 0.5 [0, 10] step=0.05 §1.6 _DetailNoiseMultiplier:
                                       //   strength of the detail noise
uniform float uContainerEdgeFadeDst;   // @param 200 [0.001, 100000] step=10 unit=m §1.6 Container
                                       //   Edge Fade: distance from the x/z walls over which
                                       //   density fades in
uniform vec4 uVolumeNoiseWeight;       // @param (1, 0.48, 0.15, 0) [0, 10] step=0.01 §1.6 Volume
                                       //   Noise Weights: weight of each channel of the volume
                                       //   noise
uniform vec3 uDetailNoiseWeight;       // @param (1, 0.5, 0.25) [0, 10] step=0.01 §1.6 Detail Noise
                                       //   Weights: weight of each channel of the detail noise
uniform int uNumStepsLight;            // @param 8 [1, 64] §1.6 Num Steps Lightning: light-march
                                       //   steps toward the sun
uniform float uFixedStepSize;          // @param 20 [0.5, 1000] step=0.5 unit=m §1.6 Fixed Step
                                       //   Modeling: primary step size
uniform int uMaxSteps;                 // @param 512 [1, 8192] beyond the thesis: cap on primary
                                       //   steps per pixel
uniform float uLightAbsortionSun;      // @param 0.03 [0, 10] step=0.001 unit=1/m §1.6 Light
                                       //   Absortion Sun: extinction along the light march
                                       //   (lightAtPos)
uniform float uLightAbsortionCloud;    // @param 0.02 [0, 10] step=0.001 unit=1/m §1.6 Light
                                       //   Absortion (Cloud): extinction along the view ray
uniform float uDarknessThreshold;      // @param 0.2 [0, 1] step=0.01 §1.6 Darkness Threshold: floor
                                       //   of lightAtPos on the dark side
uniform float uForwardScattering;      // @param 0.83 [-0.99, 0.99] step=0.01 §1.6 Forward
                                       //   Scattering: g of the forward HG lobe (_PhaseParams.x)
uniform float uBackScattering;         // @param 0.3 [-0.99, 0.99] step=0.01 §1.6 Back Scattering:
                                       //   the back lobe uses g = −this (_PhaseParams.y)
uniform float uBaseBrightness;         // @param 0.8 [0, 10] step=0.01 §1.6 Bare Brightness:
                                       //   additive base of the phase (_PhaseParams.z)
uniform float uPhaseFactor;            // @param 0.15 [0, 10] step=0.01 §1.6 Phase Factor: weight of
                                       //   the blended HG lobes (_PhaseParams.w)
uniform bool uThesisLightInversion;    // @param false beyond the thesis: reproduce the thesis's
                                       //   double inversion and 0.085 clamp (for comparison only)
uniform float uWeatherCoverage;        // @param 0 [0, 1] step=0.01 §1.6 beyond the thesis: how far
                                       //   GradientSimulator's map also thins the clouds where it
                                       //   is low (a weather map's coverage; 0 = the thesis, the
                                       //   map shapes the height band only)

uniform vec3 uCloudOffset;    // _CloudOffset: wind offset in noise units (wind × time)
uniform vec2 uCoverageShift;  // metres the coverage map has drifted along x, z (wind × time)
uniform sampler3D uVolumeNoise;   // shape ("volume") noise, RGBA
uniform sampler3D uDetailNoise;   // detail noise, RGB (+ A = 1)
uniform sampler2D uGradientNoise; // GradientSimulator's 2D coverage map, R used

const float CLOUDS_B_KM_PER_M = 0.001;            // km per metre: uCloudScale is tiles per km
const float CLOUDS_B_VOLUME_WIND = 0.1;           // noise units of volume offset per uCloudOffset
const float CLOUDS_B_DETAIL_WIND = 0.2;           // the detail noise drifts twice as fast
const float CLOUDS_B_THRESHOLD_SCALE = 0.1;       // the listing's scale of Density Threshold
const float CLOUDS_B_MIN_WEIGHT_SUM = 1.0e-6;     // floor of a noise weight sum (all 0)
const float CLOUDS_B_MIN_TEXELS = 1.0e-8;         // texels, floor before log2 (footprint 0)
const float CLOUDS_B_THESIS_MIN_LZ = 0.085;       // the thesis's clamp of |L.z|
const float CLOUDS_B_MIDPOINT = 0.5;              // fraction of a step: its midpoint
// The listing's height band: gMin in [0.1, 0.5], gMax in [gMin, 0.9] as coverage goes 0 → 1.
const float CLOUDS_B_GMIN_LO = 0.1;
const float CLOUDS_B_GMIN_HI = 0.5;
const float CLOUDS_B_GMAX_HI = 0.9;
// uWeatherCoverage's ramp: coverage below 0.3 thins to nothing, above 0.7 keeps all.
const float CLOUDS_B_COVER_LO = 0.3;
const float CLOUDS_B_COVER_HI = 0.7;

// One pixel's footprint at the sample being taken, in noise units (samplePos): the noise
// lookups read the mip level that covers it. The view march sets it for each view sample (the
// light march from there inherits it); 0 reads the base level.
float gNoiseFootprint = 0.0;

// The mip level of a noise texture for gNoiseFootprint (a fix against the thesis): implicit
// derivatives inside the march loop (its break and branches) are undefined in GLSL, and would
// follow the neighbouring fragments' jitter and, in an amortised march (app/render/amortise.py),
// rays a block of pixels apart. The level is instead the one covering a pixel's footprint at the
// sample's distance, d · 2 tan(fov/2) / H metres, the same for every way of marching. Failure
// case: a footprint of 0 (the camera on the sample) is floored at CLOUDS_B_MIN_TEXELS, a very
// negative LOD that the sampler clamps to the base level.
float CloudsBNoiseLod(sampler3D noise) {
    return log2(max(gNoiseFootprint * float(textureSize(noise, 0).x), CLOUDS_B_MIN_TEXELS));
}

// §A.4's rayBoxDistance: (dstToBox, dstInsideBox) along dir from origin, both ≥ 0; with the
// slabs' t = (bound − origin) / dir, dstA = max of the near t's, dstB = min of the far ones,
// dstToBox = max(0, dstA), dstInsideBox = max(0, dstB − dstToBox). dir need not be unit length
// (distances are in units of |dir|). Failure case: a zero component of dir (a ray parallel to a
// slab); RayBoxIntersect (glsl/common/intersect.glsl) replaces components below 1e-20 in
// magnitude by ±1e-20, since GLSL leaves x/0 unspecified and a 0/0 on a wall would be NaN, which
// gives huge finite slab distances: the exact answer for a parallel ray.
vec2 CloudsBRayBoxDistance(vec3 boundsMin, vec3 boundsMax, vec3 origin, vec3 dir) {
    vec2 t = RayBoxIntersect(origin, dir, boundsMin, boundsMax);
    float dstToBox = max(0.0, t.x);
    return vec2(dstToBox, max(0.0, t.y - dstToBox));
}

// The thesis's rayBoxDistance as lightAtPos calls it (uThesisLightInversion, for comparison
// charts and the stability test only): it is passed 1/L and divides by it again, so the slab
// distances come out as (bound − p) · L. Failure case, kept on purpose: a zero component of the
// argument divides by 0 (unspecified in GLSL); CloudsBLightAtPos's clamp of L.z avoids most.
vec2 CloudsBRayBoxDistanceThesis(vec3 boundsMin, vec3 boundsMax, vec3 origin,
                                 vec3 invDirArgument) {
    vec3 t0 = (boundsMin - origin) / invDirArgument;
    vec3 t1 = (boundsMax - origin) / invDirArgument;
    vec3 tmin = min(t0, t1);
    vec3 tmax = max(t0, t1);
    float dstA = max(max(tmin.x, tmin.y), tmin.z);
    float dstB = min(tmax.x, min(tmax.y, tmax.z));
    float dstToBox = max(0.0, dstA);
    return vec2(dstToBox, max(0.0, dstB - dstToBox));
}

// §A.3's phase, in 1/sr plus the base brightness: two Henyey–Greenstein lobes (spec/000 eq. 3.1,
// HenyeyGreenstein in glsl/common/phase.glsl), forward g = uForwardScattering and back
// g = −uBackScattering, blended 50/50, scaled by the phase factor on the base brightness:
// P.z + P.w · (0.5 HG(cos α, P.x) + 0.5 HG(cos α, −P.y)), P = _PhaseParams. cosAlpha is the
// cosine between the view ray and the direction toward the sun, in [−1, 1]. Failure case: HG at
// |g| = 1 is a delta; the parameters keep |g| ≤ 0.99.
float CloudsBPhase(float cosAlpha) {
    float blend = 0.5;
    float hg = HenyeyGreenstein(cosAlpha, uForwardScattering) * (1.0 - blend)  // spec/000 eq. 3.1
             + HenyeyGreenstein(cosAlpha, -uBackScattering) * blend;
    return uBaseBrightness + hg * uPhaseFactor;
}

// Beer's law, spec/000 eq. 3.2: the transmittance e^(−d) of an optical depth d ≥ 0, in [0, 1].
float CloudsBBeer(float d) { return exp(-d); }                 // spec/000 eq. 3.2
// The powder term, spec/000 eq. 3.3: 1 − e^(−2d), in [0, 1). The thesis passes the density, not
// an optical depth (a failure case kept as it is: it depends on the density's scale).
float CloudsBPowder(float d) { return 1.0 - exp(-2.0 * d); }   // spec/000 eq. 3.3

// The listing's remap: v from [a, b] onto [c, d], unclamped. Failure case: a = b divides by 0;
// every caller here passes a ≠ b (gMin ≥ 0.1 > 0 and gMax ≤ 0.9 < 1).
float CloudsBRemap(float v, float a, float b, float c, float d) {
    return c + (v - a) * (d - c) / (b - a);
}

// §A.5's edge weight, in [0, 1]: the density fades in over uContainerEdgeFadeDst metres from the
// x and z walls of the box (0 on a wall, 1 from Fade inside). p in world metres. Failure case: a
// Fade of 0 would divide by 0; its parameter's range starts at 1 mm.
float CloudsBEdgeWeight(vec3 p) {
    float edgeX = min(uContainerEdgeFadeDst, min(p.x - uBoundsMin.x, uBoundsMax.x - p.x));
    float edgeZ = min(uContainerEdgeFadeDst, min(p.z - uBoundsMin.z, uBoundsMax.z - p.z));
    return max(min(edgeX, edgeZ), 0.0) / uContainerEdgeFadeDst;
}

// §A.5's height gradient, in [0, 1], from the height fraction h in the box and the coverage
// value g: gMin = remap(g, 0, 1, 0.1, 0.5), gMax = remap(g, 0, 1, gMin, 0.9), then
// sat(remap(h, 0, gMin, 0, 1)) · sat(remap(h, 1, gMax, 0, 1)): 0 at h = 0 and h = 1, 1 between
// gMin and gMax. Every remap has a ≠ b (see CloudsBRemap).
float CloudsBHeightGradient(float heightPercent, float gradient) {
    float gMin = CloudsBRemap(gradient, 0.0, 1.0, CLOUDS_B_GMIN_LO, CLOUDS_B_GMIN_HI);
    float gMax = CloudsBRemap(gradient, 0.0, 1.0, gMin, CLOUDS_B_GMAX_HI);
    return saturate(CloudsBRemap(heightPercent, 0.0, gMin, 0.0, 1.0))
         * saturate(CloudsBRemap(heightPercent, 1.0, gMax, 0.0, 1.0));
}

// The coverage value in [0, 1] of GradientSimulator's map at the world point p (metres), the
// map laid once over the box's xz by (p.xz − boxMin.xz) / maxDim. Two fixes against the thesis:
// its uv had a precedence slip (BoundsMin + BoundsMax · 0.5) and truncated xy/xz, so this is the
// digest's stated intent; and the map drifts with the wind by uCoverageShift metres (the thesis
// moved only the noise, _CloudOffset, so the field the map shapes stayed put, whereas
// GradientSimulator's own Offset "moves the noise" to move a storm front). The mip level covers
// the pixel's footprint (see CloudsBNoiseLod), floored as there.
float CloudsBCoverage(vec3 p) {
    vec3 size = uBoundsMax - uBoundsMin;
    float maxDim = max(size.x, size.z);
    vec2 uv = (p.xz - uBoundsMin.xz - uCoverageShift) / maxDim;
    float texels = gNoiseFootprint / (uCloudScale * CLOUDS_B_KM_PER_M) / maxDim
                   * float(textureSize(uGradientNoise, 0).x);
    return textureLod(uGradientNoise, uv, log2(max(texels, CLOUDS_B_MIN_TEXELS))).r;
}

// The weather map's coverage factor on the base shape, in [0, 1] (beyond the thesis):
// mix(1, smoothstep(0.3, 0.7, g), uWeatherCoverage). Clear gaps and cloud banks kilometres wide
// then break the volume noise's repeating tile (Schneider's weather-map coverage: the map spans
// the box once, the noise tiles every 1/CloudScale km). uWeatherCoverage = 0 gives 1, the thesis.
float CloudsBWeatherCover(float gradient) {
    return mix(1.0, smoothstep(CLOUDS_B_COVER_LO, CLOUDS_B_COVER_HI, gradient), uWeatherCoverage);
}

// §A.4 and §A.5's sampleDensity at a world point p (metres): dimensionless, the extinction per
// uLightAbsortion* unit; ≤ 0 means no cloud. samplePos = (halfSize + p) · CloudScale · 0.001;
// volumeFBM = dot(VolumeNoise(samplePos + 0.1 CloudOffset), W_v / ΣW_v) · heightGradient
// (CloudsBHeightGradient · CloudsBEdgeWeight · CloudsBWeatherCover); volumeDensity = volumeFBM +
// 0.1 DensityThreshold; where that is positive, the detail erodes it:
// volumeDensity − (1 − detailFBM) (1 − volumeFBM)³ DetailNoiseMultiplier DensityMultiplier, with
// detailFBM = dot(DetailNoise(samplePos + 0.2 CloudOffset).rgb, W_d / ΣW_d). Failure cases: all
// weights 0 (the sums are floored at CLOUDS_B_MIN_WEIGHT_SUM, giving density 0), a box of zero
// height (size.y = 0 divides by 0; the parameters' corners are the user's to keep apart).
float CloudsBSampleDensity(vec3 p) {
    vec3 size = uBoundsMax - uBoundsMin;
    vec3 halfSize = size * 0.5;
    vec3 samplePos = (halfSize + p) * uCloudScale * CLOUDS_B_KM_PER_M;
    float heightPercent = (p.y - uBoundsMin.y) / size.y;
    float gradient = CloudsBCoverage(p);
    float heightGradient = CloudsBHeightGradient(heightPercent, gradient) * CloudsBEdgeWeight(p)
                         * CloudsBWeatherCover(gradient);

    vec4 vn = textureLod(uVolumeNoise, samplePos + uCloudOffset * CLOUDS_B_VOLUME_WIND,
                         CloudsBNoiseLod(uVolumeNoise));
    vec4 wv = uVolumeNoiseWeight / max(dot(uVolumeNoiseWeight, vec4(1.0)),
                                       CLOUDS_B_MIN_WEIGHT_SUM);
    float volumeFBM = dot(vn, wv) * heightGradient;
    float volumeDensity = volumeFBM + uDensityThreshold * CLOUDS_B_THRESHOLD_SCALE;
    if (volumeDensity > 0.0) {
        vec3 dn = textureLod(uDetailNoise, samplePos + uCloudOffset * CLOUDS_B_DETAIL_WIND,
                             CloudsBNoiseLod(uDetailNoise)).rgb;
        vec3 wd = uDetailNoiseWeight / max(dot(uDetailNoiseWeight, vec3(1.0)),
                                           CLOUDS_B_MIN_WEIGHT_SUM);
        float detailFBM = dot(dn, wd);
        float oneMinusShape = 1.0 - volumeFBM;
        float erode = oneMinusShape * oneMinusShape * oneMinusShape;
        float detailDensity = (1.0 - detailFBM) * erode * uDetailNoiseMultiplier;
        return volumeDensity - detailDensity * uDensityMultiplier;
    }
    return 0.0;
}

// §A.6's lightAtPos: the light reaching p (world metres) from the sun, in [DarknessThreshold, 1]:
// uNumStepsLight midpoint samples from p to the box's wall toward the sun, τ = Σ density · step,
// T = e^(−τ · LightAbsortionSun) (spec/000 eq. 3.2), returned as DarknessThreshold +
// T (1 − DarknessThreshold). towardSun is the unit vector toward the sun (the thesis's
// L = −_SunDir). With uThesisLightInversion the thesis's double inversion comes back, with its
// clamp |L.z| ≥ 0.085 (which leaves L.z = 0 at 0, as sign(0) = 0); otherwise L itself is passed
// and nothing is clamped. Failure case: negative densities are clamped to 0 per sample.
float CloudsBLightAtPos(vec3 p, vec3 towardSun) {
    float dIn;
    if (uThesisLightInversion) {
        vec3 L = towardSun;
        if (abs(L.z) < CLOUDS_B_THESIS_MIN_LZ) L.z = sign(L.z) * CLOUDS_B_THESIS_MIN_LZ;
        dIn = CloudsBRayBoxDistanceThesis(uBoundsMin, uBoundsMax, p, 1.0 / L).y;
    } else {
        dIn = CloudsBRayBoxDistance(uBoundsMin, uBoundsMax, p, towardSun).y;
    }
    float stepSize = dIn / float(uNumStepsLight);
    p += towardSun * stepSize * CLOUDS_B_MIDPOINT;
    float totalDensity = 0.0;
    for (int i = 0; i < uNumStepsLight; i++) {
        totalDensity += max(0.0, CloudsBSampleDensity(p) * stepSize);
        p += towardSun * stepSize;
    }
    float transmittance = CloudsBBeer(totalDensity * uLightAbsortionSun);
    return uDarknessThreshold + transmittance * (1.0 - uDarknessThreshold);
}
