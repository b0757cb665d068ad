#version 330 core
// Cloud model A, the view march: spec/001 §1.5 (ray march, Algorithm "2"), §1.6 (light march,
// Algorithm "3"), §1.7 (lighting), after Häggström 2018 / Schneider 2015, with the speed
// options the thesis described but left undone (§1.5 items 2–4, as switches) and options
// beyond it (multiple-scattering octaves, energy-conserving integration, ambient light).
// Equations: spec/001 eq. 4.16 (via cloud_model.glsl), spec/001 eq. 4.17, spec/001 eq. 4.18,
// spec/001 eq. 4.21, spec/001 eq. 4.22, spec/001 eq. 4.23.
//
// Output: the cloud layer, RGBA = (in-scattered radiance, premultiplied; view transmittance T).
// glsl/common/layer_composite.frag lays it over whatever the scene drew: out = rgb + T · scene,
// so a pixel the clouds miss (rgb = 0, T = 1) keeps the scene's value bit for bit. At location
// 1 the amortised march's aux (glsl/common/amortise.glsl): the transmittance-weighted distance
// of the cloud met (each step's distance weighted by the light that step takes away, over
// the whole 1 − T taken away), and the opaque scene's distance. Which
// pixel a fragment marches is AmortisedPixel(): itself, or one pixel of each block of an
// amortised frame (app/render/amortise.py).
//
// Per pixel
// 1. Ray interval (§1.5 item 1): the camera ray against the container — an axis-aligned box
//    [−half, al_b, −half]–[half, al_m, half], or the shell between the spheres of radius
//    R + al_b and R + al_m about (0, −R, 0) (Annex C intersections, cloud_model.glsl) — clipped
//    to the opaque scene (the scene depth texture turned into a distance along the ray) and to
//    uMaxDistance.
// 2. View march: N = uSteps samples over the interval (the thesis's 64 by default), the first
//    offset by a jitter in [0, 1) of a step against banding (the thesis's blue noise, §4): the
//    thesis's march uses interleaved gradient noise (Jimenez 2014, static per pixel, plus
//    uJitterPhase, which the reference of app/bench/clouds.py averages over); the amortised
//    march (glsl/common/amortise.glsl) a void-and-cluster blue noise whose phase moves on with
//    each refresh of the pixel; 0.5 (midpoints) with the jitter off. Each sample's density d (spec/001 eq. 4.16, cloud_model.glsl) is an extinction
//    σ = k · d / L_ref per metre, L_ref = the thesis's light step 0.5 · (al_m − al_b) / 6 (so
//    the light march's d_s below is the thesis's plain sum of 6 densities at the default
//    settings) and k = uExtinction (the thesis's alpha, a plain sum of 64 samples, has no
//    length: k = 3 makes a typical 5 km view interval about as opaque as that sum).
//    Transmittance T ← T · e^(−σ Δt); the march stops when T < uTransmittanceCutoff (early exit,
//    §1.5 item 5; the thesis's "accumulated density > 1").
// 3. Light march (§1.6) at each sample with d > 0: uLightSteps (6) samples toward the light
//    over 0.5 · (al_m − al_b) (the thesis's 0.5 · thickness, taken as the layer's thickness so
//    it does not depend on the view ray; midpoints), each displaced inside a cone by a fixed
//    kernel vector in [−1, 1]³ times uConeSpread · distance, the texture LOD raised by
//    uLightLodStep per sample, and shape-only (cheaper) samples once the accumulated d_s
//    exceeds uCheapLightThreshold (default 0.3). The sums are accumulated (erratum §1.10 item 3).
// 4. Lighting: E = L(b, d_s) · IOS(cos θ) (spec/001 eq. 4.22, spec/001 eq. 4.21,
//    spec/001 eq. 4.23), cos θ = light · view direction;
//    optional multiple-scattering octaves (Wrenninge 2013, beyond the thesis):
//       E = 2 (1 − e^(−2 b d_s)) · Σ_{i<n} B^i e^(−A^i b d_s) IOS(cos θ; c^i in_s, c^i out_s, c^i cs_i)
//    with A ≤ B enforced (A ← min(A, B)) so energy does not grow; n = 1 is spec/001 eq. 4.23
//    exactly. The in-scattered radiance is S = E · uLightScale · light radiance + ambient
//    (ambient: beyond the thesis, uAmbientRadiance from the CPU: uAmbient · light radiance
//    plus clouds.sky_ambient · the sky's ambient radiance when the light comes from the
//    day–night sky; both 0 give the thesis's model, whose direct light is 0 where d_s = 0,
//    erratum item 11).
// 5. Integration over a step of length Δt:
//       naive sum (the theses):          C += T · S · σ Δt
//       energy-conserving (Hillaire 2016): C += T · S · (1 − e^(−σ Δt))
//    (albedo 1, σ_s = σ_t); both converge to the same integral as Δt → 0.
// Speed options (spec/001 §1.5 items 2–4), each a switch:
//    distance steps:  Δt = Δt_0 + t · uStepGrowth (spec/001 eq. 4.17, with the sample's
//                     distance t as dist_inicio; uStepGrowth 0 or the switch off is the
//                     uniform march);
//    adaptive steps:  outside clouds, shape-only samples every uOutsideStepScale · Δt; on a
//                     hit, step back and march at Δt with full samples until uExitAfterEmpty
//                     empty samples in a row (shape-only density ≥ full density, so a skipped
//                     point had no cloud; thin wisps between coarse samples can be missed);
//    detail cutoff:   after uDetailCutoffSteps consecutive in-cloud samples, shape only.
// Adaptive steps are on by default: about half the march time for a mean error against a
// 512-step march within the budget `natura bench clouds` states and checks (1.5 × the uniform
// 64-step march's; app/bench/clouds.py); clouds.adaptive_steps = false is the thesis's uniform
// march, which Table 6.1's reproduction times.
//
// Failure cases
// * Steps far larger than the cloud features band (visible slices); the jitter trades the
//   bands for per-pixel noise (thesis §4), uSteps ↑ removes both.
// * Sphere shell seen from the ground near the horizon: intervals of 200+ km; uMaxDistance
//   bounds them (clouds beyond it are not drawn).
// * The light march stops at 0.5 · layer thickness: shadows from farther clouds are missed.
// * Light from below the horizon still lights the clouds from below (the sky fades its main
//   light there); axis-aligned light or view directions are safe (RayBoxIntersect guards 1/0).
// * Camera inside a cloud: the interval starts at 0; nothing special is needed.

#include "cloud_model.glsl"
#include "camera.glsl"
#include "amortise.glsl"

in vec2 vUV;
layout(location = 0) out vec4 fragColor;
layout(location = 1) out vec4 outAux;  // amortised march: (cloud distance, scene distance)

// ---- the thesis's panel (spec/001 §2) ----------------------------------------------------
uniform float uCoverage;        // @param 0.4 [0, 1] step=0.01 §1.3 Nubosidad n_g: global coverage (0 none, 1 overcast)
uniform float uDensity;         // @param 1 [0, 10] step=0.01 §1.4 Densidad d_g: global density (opacity)
uniform float uBaseHeight;      // @param 1500 [0, 20000] step=10 unit=m §1.2 Altura Base al_b: where the layer starts
uniform float uMaxHeight;       // @param 4000 [0, 20000] step=10 unit=m §1.2 Altura Máxima al_m: top of the layer
uniform float uWeatherScale;    // @param 40000 [1000, 400000] step=500 unit=m §2 Tam. climático: metres per weather-map tile
uniform float uShapeScale;      // @param 8000 [200, 100000] step=100 unit=m §2 Tam. forma: metres per shape-noise tile
uniform float uDetailScale;     // @param 1500 [50, 50000] step=50 unit=m §2 Tam. detalle: metres per detail-noise tile
uniform float uCloudHeight;     // @param 1 [0, 1] step=0.01 §1.4 multiplies the weather map's max height mc_a (the stratus map has "smaller" clouds)
uniform int uSteps;             // @param 64 [1, 1024] §1.5 Muestras: view-ray samples over the container interval
uniform int uLightSteps;        // @param 6 [0, 32] §1.6 light-march samples (0: no self-shadowing)
uniform float uAbsorption;      // @param 6 [0, 50] step=0.1 §1.7 Absorción de luz b (spec/001 eq. 4.18)
uniform float uInScatter;       // @param 0.2 [0, 0.99] step=0.01 §1.7 In scatter in_s: HG g toward the camera (spec/001 eq. 4.21)
uniform float uOutScatter;      // @param 0.1 [0, 0.99] step=0.01 §1.7 Out scatter out_s: HG −g away (spec/001 eq. 4.21)
uniform float uInVsOut;         // @param 0.5 [0, 1] step=0.01 §1.7 In o Out Scatter ivo: blend of the two lobes (spec/001 eq. 4.21)
uniform float uSilverIntensity; // @param 3 [0, 10] step=0.05 §1.7 Silver intensity cs_i (spec/001 eq. 4.20)
uniform float uSilverExponent;  // @param 2 [0, 64] step=0.5 §1.7 Silver exponent cs_e: the silver lobe's spread (spec/001 eq. 4.20)

// ---- light march and lighting details ------------------------------------------------------
uniform float uLightStepFraction;    // @param 0.5 [0.05, 2] step=0.05 §1.6 light-ray length as a fraction of the layer thickness (thesis 0.5)
uniform float uConeSpread;           // @param 0.5 [0, 2] step=0.05 §1.6 cone half-width per metre travelled toward the light
uniform float uCheapLightThreshold;  // @param 0.3 [0, 10] step=0.05 §1.6 accumulated d_s above which light samples are shape-only
uniform float uLightLodStep;         // @param 1 [0, 4] step=0.25 §1.6 texture LOD added per light sample
uniform float uAmbient;              // @param 0.3 [0, 4] step=0.01 beyond the thesis: isotropic ambient radiance as a fraction of the light's (0 = the thesis; the CPU folds it into uAmbientRadiance)
uniform float uLightScale;           // @param 10 [0, 100] step=0.1 direct light = E · this · light radiance (phase values are ~0.08/sr; the thesis remaps its sums instead)
uniform float uExtinction;           // @param 3 [0, 100] step=0.1 view-ray extinction per unit density, in 1/L_ref (the thesis's alpha = Σ of its samples; see 2.)

// ---- speed and accuracy options (beyond the thesis) ---------------------------------------------
uniform bool uJitter;                // @param true §4 per-pixel jitter of the first sample against banding (off: midpoints)
uniform bool uEnergyConserving;      // @param true Hillaire 2016 step integration (off: the theses' naive sum)
uniform int uMsOctaves;              // @param 1 [1, 8] multiple-scattering octaves (Wrenninge; 1 = the thesis's single scattering)
uniform float uMsA;                  // @param 0.5 [0, 1] step=0.01 octave extinction attenuation a (used as min(a, b))
uniform float uMsB;                  // @param 0.5 [0, 1] step=0.01 octave contribution attenuation b
uniform float uMsC;                  // @param 0.5 [0, 1] step=0.01 octave eccentricity attenuation c
uniform bool uDistanceSteps;         // @param false §1.5 spec/001 eq. 4.17: step grows with distance
uniform float uStepGrowth;           // @param 0.02 [0, 1] step=0.005 §1.5 incr_dist: metres of step per metre of distance (spec/001 eq. 4.17)
uniform bool uAdaptiveSteps;         // @param true §1.5 item 3: large shape-only steps outside clouds (off: uniform)
uniform float uOutsideStepScale;     // @param 3 [1, 16] step=0.5 §1.5 item 3: outside step / inside step
uniform int uExitAfterEmpty;         // @param 6 [1, 64] §1.5 item 3: empty samples before large steps again
uniform int uDetailCutoffSteps;      // @param 0 [0, 1024] §1.5 item 4: shape only after this many in-cloud samples in a row (0 = never)
uniform float uTransmittanceCutoff;  // @param 0.01 [0, 0.5] step=0.005 §1.5 item 5: early exit below this transmittance
uniform float uMaxDistance;          // @param 100000 [100, 1000000] step=1000 unit=m farthest cloud sample from the camera

// ---- container ---------------------------------------------------------------------------------
uniform float uBoxHalfSize;          // @param 30000 [100, 1000000] step=500 unit=m §1.5 box: horizontal half-width
uniform float uPlanetRadius;         // @param 6371000 [1000, 100000000] step=1000 unit=m §1.5 spheres: planet radius R
uniform int uContainer;              // 0 box, 1 the shell between two spheres (clouds.container)

// ---- set by app/effects/clouds/effect.py ------------------------------------------------------
uniform vec3 uLightDir;          // unit, toward the light
uniform vec3 uLightRadiance;     // linear (without uLightScale)
uniform vec3 uAmbientRadiance;   // isotropic ambient in-scattered radiance (CPU, see the header)
uniform float uDensityLength;    // L_ref in metres (see 2. above)
uniform vec2 uWeatherOffset;     // wind offsets in texture units, wrapped into [0, 1)
uniform vec2 uShapeOffset;
uniform vec2 uDetailOffset;
uniform float uCamNear;          // the projection of the scene's depth buffer
uniform float uCamFar;
uniform bool uHasSceneDepth;
uniform bool uAmortised;         // an amortised march (blue-noise jitter), else the thesis's

uniform sampler2D uWeather;      // RGBA: mc_n0, mc_n1, mc_a, mc_d
uniform sampler3D uShape;        // RGBA: f_r, f_g, f_b, f_a
uniform sampler3D uDetail;       // RGB: d_r, d_g, d_b
uniform sampler2D uSceneDepth;   // window depth in [0, 1], compare mode off

// Fixed cone kernel: vectors in [−1, 1]³ (§1.6), one per light sample (repeats past 6).
const vec3 CONE_KERNEL[6] = vec3[6](
    vec3(0.38, -0.61, 0.27), vec3(-0.72, 0.14, 0.55), vec3(0.09, 0.83, -0.41),
    vec3(-0.33, -0.25, -0.78), vec3(0.91, 0.32, -0.06), vec3(-0.47, 0.58, 0.21));

// Jimenez 2014 interleaved gradient noise in [0, 1): a static, well-spread per-pixel jitter.
float InterleavedGradientNoise(vec2 pixel) {
    return fract(52.9829189 * fract(dot(pixel, vec2(0.06711056, 0.00583715))));
}

vec3 PlanetCentre() { return vec3(0.0, -uPlanetRadius, 0.0); }

// The height whose fraction spec/001 eq. 4.4 takes: y in the box, radius − R in the shell.
float LayerHeight(vec3 p) {
    return uContainer == 1 ? length(p - PlanetCentre()) - uPlanetRadius : p.y;
}

// Density at a world point (spec/001 §1.4: HeightFraction, then CloudDensityFromSamples, i.e.
// spec/001 eq. 4.16, in cloud_model.glsl), with early outs that skip texture fetches where the
// result is 0 anyway; withDetail false is the shape-only density.
float SampleDensity(vec3 p, bool withDetail, float lod) {
    float h = LayerHeight(p);
    if (h <= uBaseHeight || h >= uMaxHeight) return 0.0;
    if (uContainer == 0 && (abs(p.x) > uBoxHalfSize || abs(p.z) > uBoxHalfSize)) return 0.0;
    float pa = HeightFraction(h, uBaseHeight, uMaxHeight);
    vec4 weather = textureLod(uWeather, p.xz / uWeatherScale - uWeatherOffset, 0.0);
    weather.b *= uCloudHeight;
    if (HeightDensity(pa, uDensity, weather.a) <= 0.0 || HeightShape(pa, weather.b) <= 0.0
        || uCoverage * Nubosidad(weather.rg, uCoverage) <= 0.0) return 0.0;
    vec3 q = vec3(p.x, p.z, p.y);
    vec4 shape = textureLod(uShape, q / uShapeScale - vec3(uShapeOffset, 0.0), lod);
    vec3 detail = vec3(0.0);
    if (withDetail) detail = textureLod(uDetail, q / uDetailScale - vec3(uDetailOffset, 0.0), lod).rgb;
    return CloudDensityFromSamples(weather, shape, detail, pa, uCoverage, uDensity, withDetail);
}

// d_s: accumulated density toward the light, in units of L_ref (the thesis's sum at defaults).
float LightOpticalDepth(vec3 p) {
    float thickness = max(uMaxHeight - uBaseHeight, 1.0);
    float stepLen = uLightStepFraction * thickness / float(max(uLightSteps, 1));
    float ds = 0.0;
    for (int i = 0; i < uLightSteps; ++i) {
        float dist = (float(i) + 0.5) * stepLen;
        vec3 q = p + uLightDir * dist + CONE_KERNEL[i % 6] * (uConeSpread * dist);
        bool cheap = ds > uCheapLightThreshold;
        ds += SampleDensity(q, !cheap, float(i) * uLightLodStep) * (stepLen / uDensityLength);
    }
    return ds;
}

// spec/001 eq. 4.23: E = L(b, d_s) · IOS(cos θ), with the powder L of spec/001 eq. 4.22 written
// out, and the multiple-scattering octaves when uMsOctaves > 1.
float LightEnergy(float ds, float cosTheta) {
    float b = uAbsorption;
    float powder = 2.0 * (1.0 - Beer(b, 2.0 * ds));
    float a = min(uMsA, uMsB);
    float sum = 0.0, ea = 1.0, eb = 1.0, ec = 1.0;
    for (int i = 0; i < uMsOctaves; ++i) {
        sum += eb * Beer(b * ea, ds) * InOutScatter(cosTheta, uInScatter * ec, uOutScatter * ec, uInVsOut,
                                                    uSilverIntensity * ec, uSilverExponent);
        ea *= a;
        eb *= uMsB;
        ec *= uMsC;
    }
    return powder * sum;
}

// (t_start, t_end) of the camera ray inside the container, t_start ≥ 0; t_end ≤ t_start: none.
vec2 ContainerInterval(vec3 origin, vec3 dir) {
    if (uContainer == 0) {
        vec2 t = RayBoxIntersect(origin, dir, vec3(-uBoxHalfSize, uBaseHeight, -uBoxHalfSize),
                                 vec3(uBoxHalfSize, uMaxHeight, uBoxHalfSize));
        return vec2(max(t.x, 0.0), t.y);
    }
    vec3 c = PlanetCentre();
    float rInner = uPlanetRadius + uBaseHeight, rOuter = uPlanetRadius + uMaxHeight;
    vec2 tOuter, tInner;
    if (!RaySphereIntersect(origin, dir, c, rOuter, tOuter)) return vec2(0.0, -1.0);
    bool hitsInner = RaySphereIntersect(origin, dir, c, rInner, tInner);
    float r = length(origin - c);
    if (r < rInner) return vec2(max(tInner.y, 0.0), tOuter.y);          // below the layer
    float start = max(tOuter.x, 0.0);                                    // in or above the layer
    float end = (hitsInner && tInner.x > 0.0) ? tInner.x : tOuter.y;     // stop at the inner sphere
    return vec2(start, end);
}

// Distance along the ray to the opaque scene (1e30: nothing drawn there).
float SceneDistance(vec3 dir, ivec2 pixel) {
    if (!uHasSceneDepth) return 1e30;
    float depth = texelFetch(uSceneDepth, pixel, 0).r;
    if (depth >= 1.0) return 1e30;
    float zNdc = depth * 2.0 - 1.0;
    float viewZ = 2.0 * uCamNear * uCamFar / (uCamFar + uCamNear - zNdc * (uCamFar - uCamNear));
    return viewZ / max(dot(dir, uCamForward), 1e-6);
}

void main() {
    if (AmortisePadding()) discard;  // a banded grid's padding
    // the full-resolution pixel this fragment stands for (itself, or one pixel of each block
    // of an amortised frame)
    ivec2 pixel = AmortisedPixel();
    vec3 dir = CameraRayDirection(AmortisedUV(pixel));
    vec3 origin = uCameraPos;
    vec2 seg = ContainerInterval(origin, dir);
    float sceneDist = SceneDistance(dir, pixel);
    outAux = AmortiseAux(AMORTISE_FAR, sceneDist);
    seg.y = min(seg.y, min(sceneDist, uMaxDistance));
    if (!(seg.y > seg.x)) { fragColor = vec4(0.0, 0.0, 0.0, 1.0); return; }

    float dt0 = (seg.y - seg.x) / float(max(uSteps, 1));
    float jitter = 0.5;
    if (uJitter) {
        jitter = uAmortised ? AmortiseJitter(pixel)
                            : fract(InterleavedGradientNoise(vec2(pixel) + 0.5) + uJitterPhase);
    }
    float cosTheta = dot(uLightDir, dir);
    vec3 ambient = uAmbientRadiance;
    vec3 direct = uLightScale * uLightRadiance;

    float T = 1.0;
    vec3 C = vec3(0.0);
    float tSum = 0.0;  // each step's distance × the transmittance it removes: the cloud's distance for reprojection
    float t = seg.x + jitter * dt0;
    bool fine = !uAdaptiveSteps;
    int empty = 0, inCloud = 0;
    int maxIterations = 4 * max(uSteps, 1) + 16;
    for (int i = 0; i < maxIterations; ++i) {
        if (t >= seg.y) break;
        float dt = dt0 + (uDistanceSteps ? t * uStepGrowth : 0.0);
        vec3 p = origin + dir * t;
        if (!fine) {
            float coarse = SampleDensity(p, false, 0.0);
            if (coarse > 0.0) {
                fine = true;
                empty = 0;
                t = max(t - (uOutsideStepScale - 1.0) * dt, seg.x + jitter * dt0);
            } else {
                t += uOutsideStepScale * dt;
            }
            continue;
        }
        bool detail = !(uDetailCutoffSteps > 0 && inCloud >= uDetailCutoffSteps);
        float d = SampleDensity(p, detail, 0.0);
        if (d > 0.0) {
            empty = 0;
            inCloud += 1;
            float sigma = uExtinction * d / uDensityLength;
            float stepT = exp(-sigma * dt);
            float ds = uLightSteps > 0 ? LightOpticalDepth(p) : 0.0;
            vec3 S = LightEnergy(ds, cosTheta) * direct + ambient;
            C += uEnergyConserving ? T * S * (1.0 - stepT) : T * S * (sigma * dt);
            tSum += T * (1.0 - stepT) * t;
            T *= stepT;
            if (T < uTransmittanceCutoff) break;
        } else {
            inCloud = 0;
            empty += 1;
            if (uAdaptiveSteps && empty >= uExitAfterEmpty) fine = false;
        }
        t += dt;
    }
    fragColor = vec4(C, T);
    if (T < 0.9999) outAux.x = tSum / (1.0 - T);
}
