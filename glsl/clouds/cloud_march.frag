#version 330 core
// Cloud model A, the view march: spec/001 §1.5 (ray march, Algorithm "2"), §1.6 (light march,
// Algorithm "3") and §1.7 (lighting), after Häggström 2018 / Schneider 2015. It adds, as
// switches, the speed options the thesis described but left undone (§1.5 items 2–4), and beyond
// it multiple-scattering octaves, energy-conserving integration and ambient light. The density
// and lighting terms are cloud_model.glsl's; this file marches them. Each function below states
// its equations, units and failure case; main() walks through the march step by step.
// Output: RGBA = (in-scattered linear radiance, premultiplied; view transmittance T), laid over
// the scene by glsl/common/layer_composite.frag as rgb + T · scene (a miss, rgb = 0 and T = 1,
// keeps the scene bit for bit). Failure cases guarded: empty or reversed intervals, a division
// by an axis-aligned ray, the sphere shell's 200+ km horizon intervals (uMaxDistance), and the
// march loop's length (an iteration bound).

#include "cloud_model.glsl"
#include "camera.glsl"
#include "amortise.glsl"

in vec2 vUV;
layout(location = 0) out vec4 fragColor;
// At location 1 the amortised march's aux (glsl/common/amortise.glsl): the cloud's distance
// (each step's distance weighted by the light it takes away, over the whole 1 − T) and the
// opaque scene's distance, both in metres along the ray.
layout(location = 1) out vec4 outAux;  // amortised march: (cloud distance, scene distance)

// ---- the thesis's panel (spec/001 §2) ---------------------------------------------------
uniform float uCoverage;        // @param 0.4 [0, 1] step=0.01 §1.3 Nubosidad n_g: global coverage
                                //   (0 none, 1 overcast)
uniform float uDensity;         // @param 1 [0, 10] step=0.01 §1.4 Densidad d_g: global density
                                //   (opacity)
uniform float uBaseHeight;      // @param 1500 [0, 20000] step=10 unit=m §1.2 Altura Base al_b:
                                //   where the layer starts
uniform float uMaxHeight;       // @param 4000 [0, 20000] step=10 unit=m §1.2 Altura Máxima al_m:
                                //   top of the layer
uniform float uWeatherScale;    // @param 40000 [1000, 400000] step=500 unit=m §2 Tam. climático:
                                //   metres per weather-map tile
uniform float uShapeScale;      // @param 8000 [200, 100000] step=100 unit=m §2 Tam. forma: metres
                                //   per shape-noise tile
uniform float uDetailScale;     // @param 1500 [50, 50000] step=50 unit=m §2 Tam. detalle: metres
                                //   per detail-noise tile
uniform float uCloudHeight;     // @param 1 [0, 1] step=0.01 §1.4 multiplies the weather map's max
                                //   height mc_a (the stratus map has "smaller" clouds)
uniform int uSteps;             // @param 64 [1, 1024] §1.5 Muestras: view-ray samples over the
                                //   container interval
uniform int uLightSteps;        // @param 6 [0, 32] §1.6 light-march samples (0: no self-shadowing)
uniform float uAbsorption;      // @param 6 [0, 50] step=0.1 §1.7 Absorción de luz b
                                //   (spec/001 eq. 4.18)
uniform float uInScatter;       // @param 0.2 [0, 0.99] step=0.01 §1.7 In scatter in_s: HG g toward
                                //   the camera (spec/001 eq. 4.21)
uniform float uOutScatter;      // @param 0.1 [0, 0.99] step=0.01 §1.7 Out scatter out_s: HG −g away
                                //   (spec/001 eq. 4.21)
uniform float uInVsOut;         // @param 0.5 [0, 1] step=0.01 §1.7 In o Out Scatter ivo: blend of
                                //   the two lobes (spec/001 eq. 4.21)
uniform float uSilverIntensity; // @param 3 [0, 10] step=0.05 §1.7 Silver intensity cs_i
                                //   (spec/001 eq. 4.20)
uniform float uSilverExponent;  // @param 2 [0, 64] step=0.5 §1.7 Silver exponent cs_e: the silver
                                //   lobe's spread (spec/001 eq. 4.20)

// ---- light march and lighting details ------------------------------------------------------
uniform float uLightStepFraction;    // @param 0.5 [0.05, 2] step=0.05 §1.6 light-ray length as a
                                     //   fraction of the layer thickness (thesis 0.5)
uniform float uConeSpread;           // @param 0.5 [0, 2] step=0.05 §1.6 cone half-width per metre
                                     //   travelled toward the light
uniform float uCheapLightThreshold;  // @param 0.3 [0, 10] step=0.05 §1.6 accumulated d_s above
                                     //   which light samples are shape-only
uniform float uLightLodStep;         // @param 1 [0, 4] step=0.25 §1.6 texture LOD added
                                     //   per light sample
uniform float uAmbient;              // @param 0.3 [0, 4] step=0.01 beyond the thesis: isotropic
                                     //   ambient radiance as a fraction of the light's (0 = the
                                     //   thesis; the CPU folds it into uAmbientRadiance)
uniform float uLightScale;           // @param 10 [0, 100] step=0.1 direct light = E · this · light
                                     //   radiance (phase values are ~0.08/sr; the thesis remaps its
                                     //   sums instead)
uniform float uExtinction;           // @param 3 [0, 100] step=0.1 view-ray extinction per unit
                                     //   density, in 1/L_ref (the thesis's alpha = Σ of its
                                     //   samples; see 2.)

// ---- speed and accuracy options (beyond the thesis) ------------------------------------
uniform bool uJitter;                // @param true §4 per-pixel jitter of the first sample against
                                     //   banding (off: midpoints)
uniform bool uEnergyConserving;      // @param true Hillaire 2016 step integration (off: the theses'
                                     //   naive sum)
uniform int uMsOctaves;              // @param 1 [1, 8] multiple-scattering octaves (Wrenninge;
                                     //   1 = the thesis's single scattering)
uniform float uMsA;                  // @param 0.5 [0, 1] step=0.01 octave extinction attenuation a
                                     //   (used as min(a, b))
uniform float uMsB;                  // @param 0.5 [0, 1] step=0.01 octave
                                     //   contribution attenuation b
uniform float uMsC;                  // @param 0.5 [0, 1] step=0.01 octave
                                     //   eccentricity attenuation c
uniform bool uDistanceSteps;         // @param false §1.5 spec/001 eq. 4.17: step grows with
                                     //   distance
uniform float uStepGrowth;           // @param 0.02 [0, 1] step=0.005 §1.5 incr_dist: metres of step
                                     //   per metre of distance (spec/001 eq. 4.17)
uniform bool uAdaptiveSteps;         // @param true §1.5 item 3: large shape-only steps outside
                                     //   clouds (off: uniform)
uniform float uOutsideStepScale;     // @param 3 [1, 16] step=0.5 §1.5 item 3: outside
                                     //   step / inside step
uniform int uExitAfterEmpty;         // @param 6 [1, 64] §1.5 item 3: empty samples before large
                                     //   steps again
uniform int uDetailCutoffSteps;      // @param 0 [0, 1024] §1.5 item 4: shape only after this many
                                     //   in-cloud samples in a row (0 = never)
uniform float uTransmittanceCutoff;  // @param 0.01 [0, 0.5] step=0.005 §1.5 item 5: early exit
                                     //   below this transmittance
uniform float uMaxDistance;          // @param 100000 [100, 1000000] step=1000 unit=m farthest cloud
                                     //   sample from the camera

// ---- container ---------------------------------------------------------------------------
uniform float uBoxHalfSize;          // @param 30000 [100, 1000000] step=500 unit=m §1.5 box:
                                     //   horizontal half-width
uniform float uPlanetRadius;         // @param 6371000 [1000, 100000000] step=1000 unit=m §1.5
                                     //   spheres: planet radius R
uniform int uContainer;              // 0 box, 1 the shell between two spheres (clouds.container)

// ---- set by app/effects/clouds/effect.py --------------------------------------------------
uniform vec3 uLightDir;          // unit, toward the light
uniform vec3 uLightRadiance;     // linear (without uLightScale)
uniform vec3 uAmbientRadiance;   // isotropic ambient in-scattered radiance (CPU, see main, 4.)
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

const float IGN_SCALE = 52.9829189;                  // Jimenez 2014's magic numbers
const vec2 IGN_PIXEL_WEIGHTS = vec2(0.06711056, 0.00583715);
const float MIN_THICKNESS = 1.0;                     // m, floor of the layer's thickness
const float MIDPOINT = 0.5;                          // fraction of a step: its midpoint
const float PIXEL_CENTRE = 0.5;                      // pixels, from a corner to the centre
const float NO_SCENE = 1e30;                         // m, the distance of "nothing drawn"
const float MIN_FORWARD_COS = 1e-6;                  // floor of cos(ray, camera forward)
const int MAX_ITERATIONS_PER_STEP = 4;               // march-loop bound: 4 N + 16 iterations
const int EXTRA_ITERATIONS = 16;
const float OPAQUE_T = 0.9999;                       // below it the aux gets a cloud distance

// Jimenez 2014 interleaved gradient noise: a static, well-spread per-pixel jitter in [0, 1)
// from a pixel position in pixels. Any pixel is valid (fract keeps the result in range).
float InterleavedGradientNoise(vec2 pixel) {
    return fract(IGN_SCALE * fract(dot(pixel, IGN_PIXEL_WEIGHTS)));
}

// The centre of the planet in world metres: (0, −R, 0), so that the ground at the origin is at
// height 0.
vec3 PlanetCentre() { return vec3(0.0, -uPlanetRadius, 0.0); }

// The height in metres whose fraction spec/001 eq. 4.4 takes (HeightFraction, cloud_model.glsl):
// y in the box, radius − R in the shell.
float LayerHeight(vec3 p) {
    return uContainer == 1 ? length(p - PlanetCentre()) - uPlanetRadius : p.y;
}

// The cloud density at a world point p (metres), dimensionless, ≥ 0: spec/001 §1.4's
// HeightFraction, then CloudDensityFromSamples (cloud_model.glsl), i.e. spec/001 eq. 4.16.
// withDetail false gives the shape-only density (never below the full one); lod is the texture
// LOD the light march raises. Early outs skip the texture fetches wherever the result would be 0
// anyway: outside the layer or the box, or where the weather map has no cloud. The weather map
// is read at LOD 0 always; the 3D noises are read with z = height (q swaps y and z).
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
    if (withDetail) {
        detail = textureLod(uDetail, q / uDetailScale - vec3(uDetailOffset, 0.0), lod).rgb;
    }
    return CloudDensityFromSamples(weather, shape, detail, pa, uCoverage, uDensity, withDetail);
}

// The light march (spec/001 §1.6, Algorithm "3"): d_s, the density accumulated from p (metres)
// toward the light, in units of L_ref = uDensityLength (so at the default settings it is the
// thesis's plain sum of 6 densities). uLightSteps midpoint samples over uLightStepFraction ·
// (al_m − al_b) (the thesis's 0.5 · thickness, taken as the layer's so that it does not depend
// on the view ray), each pushed sideways inside a cone by CONE_KERNEL · uConeSpread · distance,
// the texture LOD raised by uLightLodStep per sample, and shape-only (cheaper) samples once d_s
// exceeds uCheapLightThreshold. The sum accumulates (erratum §1.10 item 3: the printed algorithm
// does not). Failure case: clouds beyond the light ray's length cast no shadow here; a layer
// thinner than MIN_THICKNESS is marched as that thick.
float LightOpticalDepth(vec3 p) {
    float thickness = max(uMaxHeight - uBaseHeight, MIN_THICKNESS);
    float stepLen = uLightStepFraction * thickness / float(max(uLightSteps, 1));
    float ds = 0.0;
    for (int i = 0; i < uLightSteps; ++i) {
        float dist = (float(i) + MIDPOINT) * stepLen;
        vec3 q = p + uLightDir * dist + CONE_KERNEL[i % 6] * (uConeSpread * dist);
        bool cheap = ds > uCheapLightThreshold;
        ds += SampleDensity(q, !cheap, float(i) * uLightLodStep) * (stepLen / uDensityLength);
    }
    return ds;
}

// The light energy a sample sends toward the camera, per unit light (dimensionless, 1/sr through
// the phase functions): spec/001 eq. 4.23, E = L(b, d_s) · IOS(cos θ), with the powder L of
// spec/001 eq. 4.22 written out as 2 (1 − e^(−2 b d_s)) times the Beer term of spec/001 eq. 4.18,
// and IOS the in/out-scatter blend of spec/001 eq. 4.21 (InOutScatter, cloud_model.glsl).
// cosTheta = light · view direction. With uMsOctaves = n > 1, Wrenninge 2013's
// multiple-scattering octaves (beyond the thesis):
//   E = 2 (1 − e^(−2 b d_s)) · Σ_{i<n} B^i e^(−A^i b d_s) IOS(cos θ; c^i in_s, c^i out_s, c^i cs_i)
// with A ← min(A, B), so the energy cannot grow; n = 1 is spec/001 eq. 4.23 exactly. Failure
// case: at d_s = 0 the direct light is 0 (erratum item 11), which the ambient term of main fills.
// Light from below the horizon still lights the clouds from below (the sky fades it there).
float LightEnergy(float ds, float cosTheta) {
    float b = uAbsorption;
    float powder = 2.0 * (1.0 - Beer(b, 2.0 * ds));
    float a = min(uMsA, uMsB);
    float sum = 0.0, ea = 1.0, eb = 1.0, ec = 1.0;
    for (int i = 0; i < uMsOctaves; ++i) {
        sum += eb * Beer(b * ea, ds) * InOutScatter(cosTheta, uInScatter * ec, uOutScatter * ec,
                                                    uInVsOut, uSilverIntensity * ec,
                                                    uSilverExponent);
        ea *= a;
        eb *= uMsB;
        ec *= uMsC;
    }
    return powder * sum;
}

// The march's interval (§1.5 item 1): (t_start, t_end) in metres of the camera ray inside the
// container, t_start ≥ 0; t_end ≤ t_start means none. The container is the box
// [−half, al_b, −half]–[half, al_m, half] or the shell between the spheres of radius R + al_b
// and R + al_m about PlanetCentre() (Annex C intersections, glsl/common/intersect.glsl). A camera
// inside the layer (or a cloud) starts at 0. Failure cases: axis-aligned rays are safe
// (RayBoxIntersect guards 1/0); from the ground near the horizon the shell gives intervals of
// 200+ km, which main clips to uMaxDistance (clouds beyond it are not drawn).
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

// The distance in metres along the unit ray dir to the opaque scene at a pixel: the window depth
// in [0, 1] turned into view z (the scene's perspective projection, uCamNear–uCamFar), then into
// a distance along the ray. NO_SCENE where nothing was drawn (depth 1) or no depth is bound; a
// ray at right angles to the camera's forward axis is floored at MIN_FORWARD_COS.
float SceneDistance(vec3 dir, ivec2 pixel) {
    if (!uHasSceneDepth) return NO_SCENE;
    float depth = texelFetch(uSceneDepth, pixel, 0).r;
    if (depth >= 1.0) return NO_SCENE;
    float zNdc = depth * 2.0 - 1.0;
    float viewZ = 2.0 * uCamNear * uCamFar / (uCamFar + uCamNear - zNdc * (uCamFar - uCamNear));
    return viewZ / max(dot(dir, uCamForward), MIN_FORWARD_COS);
}

// The view march (spec/001 §1.5, Algorithm "2"), per pixel:
// 1. The interval: ContainerInterval, clipped to the opaque scene (SceneDistance) and to
//    uMaxDistance. Which pixel a fragment marches is AmortisedPixel(): itself, or one pixel of
//    each block of an amortised frame (app/render/amortise.py).
// 2. N = uSteps samples of step Δt_0 over the interval (the thesis's 64), the first offset by a
//    jitter in [0, 1) of a step against banding (the thesis's blue noise, §4): the thesis's
//    march uses InterleavedGradientNoise plus uJitterPhase (which the reference of
//    app/bench/clouds.py averages over), the amortised march amortise.glsl's void-and-cluster
//    blue noise, moving on with each refresh; MIDPOINT with the jitter off. Each density d
//    (SampleDensity) is an extinction σ = k · d / L_ref in 1/m, L_ref = uDensityLength, the
//    thesis's light step 0.5 · (al_m − al_b) / 6, and k = uExtinction (the thesis's alpha, a sum
//    of 64 samples, has no length: k = 3 makes a typical 5 km interval about as opaque as that
//    sum). T ← T · e^(−σ Δt); the march stops when T < uTransmittanceCutoff (early exit, §1.5
//    item 5; the thesis's "accumulated density > 1").
// 3. The light march (LightOpticalDepth) at each sample with d > 0 gives d_s.
// 4. The in-scattered radiance S = LightEnergy · uLightScale · light radiance + ambient, the
//    ambient (beyond the thesis) uAmbientRadiance from the CPU: uAmbient · light radiance, plus
//    clouds.sky_ambient · the sky's ambient radiance when the day–night sky gives the light;
//    both 0 give the thesis's model.
// 5. Over a step Δt, albedo 1 (σ_s = σ_t): the naive sum of the theses adds T · S · σ Δt, the
//    energy-conserving one (Hillaire 2016) T · S · (1 − e^(−σ Δt)); both converge to the same
//    integral as Δt → 0.
// The speed options (spec/001 §1.5 items 2–4), each a switch:
// * distance steps: Δt = Δt_0 + t · uStepGrowth, spec/001 eq. 4.17 with the sample's distance t
//   as dist_inicio (uStepGrowth 0 or the switch off is the uniform march);
// * adaptive steps (on by default): outside clouds, shape-only samples every
//   uOutsideStepScale · Δt; on a hit, step back and march at Δt with full samples until
//   uExitAfterEmpty empty samples in a row. The shape-only density is never below the full one,
//   so a skipped point had no cloud; only wisps thinner than a coarse step can be missed. It
//   halves the march time for a mean error against a 512-step march within the budget
//   `natura bench clouds` states and checks (1.5 × the uniform 64-step march's;
//   app/bench/clouds.py); clouds.adaptive_steps = false is the thesis's uniform march, which
//   Table 6.1's reproduction times;
// * detail cutoff: after uDetailCutoffSteps in-cloud samples in a row, shape only.
// Failure cases: steps far larger than the cloud's features band (visible slices), which the
// jitter trades for per-pixel noise (§4) and uSteps ↑ removes; an empty or reversed interval
// (including NaN) returns the clear layer; the loop is bounded at MAX_ITERATIONS_PER_STEP · N +
// EXTRA_ITERATIONS iterations, room for the adaptive march's steps back.
void main() {
    if (AmortisePadding()) discard;  // a banded grid's padding
    ivec2 pixel = AmortisedPixel();
    vec3 dir = CameraRayDirection(AmortisedUV(pixel));
    vec3 origin = uCameraPos;
    vec2 seg = ContainerInterval(origin, dir);
    float sceneDist = SceneDistance(dir, pixel);
    outAux = AmortiseAux(AMORTISE_FAR, sceneDist);
    seg.y = min(seg.y, min(sceneDist, uMaxDistance));
    if (!(seg.y > seg.x)) { fragColor = vec4(0.0, 0.0, 0.0, 1.0); return; }

    float dt0 = (seg.y - seg.x) / float(max(uSteps, 1));
    float jitter = MIDPOINT;
    if (uJitter) {
        jitter = uAmortised
            ? AmortiseJitter(pixel)
            : fract(InterleavedGradientNoise(vec2(pixel) + PIXEL_CENTRE) + uJitterPhase);
    }
    float cosTheta = dot(uLightDir, dir);
    vec3 ambient = uAmbientRadiance;
    vec3 direct = uLightScale * uLightRadiance;

    float T = 1.0;
    vec3 C = vec3(0.0);
    float tSum = 0.0;  // Σ step distance × transmittance removed: the cloud's distance (aux)
    float t = seg.x + jitter * dt0;
    bool fine = !uAdaptiveSteps;
    int empty = 0, inCloud = 0;
    int maxIterations = MAX_ITERATIONS_PER_STEP * max(uSteps, 1) + EXTRA_ITERATIONS;
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
    if (T < OPAQUE_T) outAux.x = tSum / (1.0 - T);
}
