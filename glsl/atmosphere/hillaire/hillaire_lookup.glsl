// Method 4, beyond the thesis: what a scene's composite pass calls to read Hillaire's LUTs
// (Hillaire 2020 §4 transmittance, §5.3 sky-view, §5.4 aerial perspective, §6 space views).
// Include this file and bind the six LUTs (transmittance, multiple scattering, sky-view ×2,
// aerial perspective ×2) with HillaireLuts.bind (app/effects/planet/hillaire.py), which also
// sets every uHillaire* uniform; the scene sets model.glsl's uniforms and camera.glsl's camera,
// the one the LUTs were updated with this frame. Radiance is linear, uSunIntensity × the
// integrals (an illuminance, as in the thesis's spec/002 §1.5: method 4 with uHillaireMsScale
// = 0 converges to method 1 as its steps grow); the sun disk is not included.
// Failure cases guarded: a camera above the atmosphere or a mesh past the volume's range (the
// per-pixel march takes over), t ≤ 0 (no scattering, T = 1), G → ±1 (the phase clamps). Not
// guarded: a volume built for another camera is drawn along the wrong rays.
#include "hillaire_common.glsl"
#include "skyview.glsl"
#include "camera.glsl"

// HILLAIRE_MARCH says at compile time what a program contains: 1 (the default) the LUT lookups
// and the per-pixel march, chosen per pixel; 0 the lookups alone (the camera inside the
// atmosphere and every mesh within the volume's range: the usual case); 2 the march alone (the
// camera above the blend band). A software rasteriser runs every branch a program contains, so
// the march must be compiled out, not skipped.
#ifndef HILLAIRE_MARCH
#define HILLAIRE_MARCH 1
#endif

uniform sampler2D uHillaireSkyViewRayleighMs;   // sky-view target 0: rgb, a = ∫ρ_R dt
uniform sampler2D uHillaireSkyViewMie;          // sky-view target 1: rgb, a = ∫ρ_M dt
uniform sampler3D uHillaireApRayleighMs;        // aerial-perspective volume 0: rgb, a = ∫ρ_R dt
uniform sampler3D uHillaireApMie;               // aerial-perspective volume 1: rgb, a = ∫ρ_M dt
uniform float uHillaireApRange;                 // m, distance of the last slice
uniform float uHillaireSpaceWeight;             // 0: LUTs valid; 1: per-pixel march only
uniform int uHillaireMarchSteps;                // samples of the fallback march
uniform float uHillaireGroundAngle;   // β = HillaireGroundAngle(camera height), from the CPU
uniform float uHillaireHorizonCos;    // HillaireHorizonCosine(camera height), from the CPU
// the camera's own source term per unit sun intensity, without the phases (from the CPU):
uniform vec3 uHillaireSourceRayleigh;   // T_sun σ_R at the camera
uniform vec3 uHillaireSourceMie;        // T_sun σ^s_M at the camera
uniform vec3 uHillaireSourceMultiple;   // σ_s Ψ_ms at the camera (0 with multiple scattering off)

const float HILLAIRE_MIN_SIN2 = 1.0e-12;       // sin² μ · sin² μ_s below which φ is undefined
const float HILLAIRE_MIN_TRANSMITTANCE = 1.0e-30; // floor of a ratio's denominator (T ∈ [0, 1])
const float HILLAIRE_AP_BLEND_START = 0.9;  // fraction of uHillaireApRange: the march starts
const float HILLAIRE_AP_BLEND_WIDTH = 0.1;  // fraction of uHillaireApRange: ... and takes over

// (μ, ν, μ_s, cos φ) of a unit direction in the camera's local vertical frame: view zenith,
// view–sun and sun zenith cosines, and the cosine of the azimuth between view and sun. Every
// cosine is clamped into [−1, 1]; cos φ is 1 where either direction is vertical.
vec4 HillaireViewAngles(vec3 viewDir) {
    vec3 up = CameraUp();
    float mu = ClampCosine(dot(viewDir, up));
    float muS = ClampCosine(dot(uSunDir, up));
    float nu = ClampCosine(dot(viewDir, uSunDir));
    // cos φ between the horizontal parts v − μ up and s − μ_s up, from the cosines alone:
    // (ν − μ μ_s) / sqrt((1 − μ²)(1 − μ_s²)) — no vectors formed per pixel (1 when either is
    // vertical, where φ is undefined and the sky-view LUT does not depend on it)
    float d = (1.0 - mu * mu) * (1.0 - muS * muS);
    float cosPhi = d > HILLAIRE_MIN_SIN2 ? (nu - mu * muS) * inversesqrt(d) : 1.0;
    return vec4(mu, nu, muS, ClampCosine(cosPhi));
}

vec3 HillaireTransmittance(float t, vec3 viewDir);

// The same integral as the LUTs (Hillaire 2020 eq. 1), marched for one pixel from the camera
// (or from the entry point, seen from space, Hillaire 2020 §6) to maxDist (m), with
// uHillaireMarchSteps samples: linear radiance rgb and mean transmittance a, and the per-channel
// transmittance. A ray that misses the atmosphere gives (0, 0, 0, 1) and T = 1.
vec4 HillaireMarch(vec3 viewDir, float maxDist, out vec3 transmittance) {
    vec4 a = HillaireViewAngles(viewDir);
    float h0 = uHillaireCameraHeight;
    vec2 seg = HillaireRaySegment(h0, a.x, maxDist);
    transmittance = vec3(1.0);
    if (seg.y <= seg.x) return vec4(0.0, 0.0, 0.0, 1.0);
    HillaireInScatter acc = HillaireIntegrateSegment(h0, a.x, a.z, a.y, seg.x, seg.y,
                                                     uHillaireMarchSteps, true);
    transmittance = exp(-acc.opticalDepth);
    return vec4(HillaireRadiance(acc, a.y), HillaireMean(transmittance));
}

// The sky-view LUT (Hillaire 2020 §5.3) for the unit direction viewDir: linear radiance (no sun
// disk; a ray that hits the ground gets the in-scattering up to it) and the per-channel
// transmittance of the whole ray, to the top or the ground, from two bilinear reads. The LUT
// holds the phased Rayleigh + multiple scattering and the phase-free Mie; its alphas hold the
// density integrals (∫ρ_R dt, ∫ρ_M dt), so T = exp(−(β^ext_R x + β^ext_M y)). With
// HILLAIRE_OZONE (ozone on: a third integral the alphas have no room for) a ray that rises into
// the layer (above OZONE_BOTTOM) takes T from the transmittance LUT instead, which holds ozone.
void HillaireSkyViewLookup(vec3 viewDir, out vec3 radiance, out vec3 transmittance) {
    vec4 a = HillaireViewAngles(viewDir);
    vec2 size = vec2(textureSize(uHillaireSkyViewRayleighMs, 0));
    vec2 uv = HillaireSkyViewUvAt(a.x, a.w, size, uHillaireGroundAngle, uHillaireHorizonCos);
    vec4 rayleighMs = texture(uHillaireSkyViewRayleighMs, uv);
    vec4 mie = texture(uHillaireSkyViewMie, uv);
    radiance = uSunIntensity * (rayleighMs.rgb + PhaseMieCornetteShanks(a.y, uMieG) * mie.rgb);
#ifdef HILLAIRE_OZONE
    // a ray to the ground from below the layer meets no ozone (its highest point is its start)
    bool below = HillaireRayHitsGround(uHillaireCameraHeight, a.x)
                 && uHillaireCameraHeight <= OZONE_BOTTOM;
    transmittance = below ? TransmittanceFromDepths(vec2(rayleighMs.a, mie.a))
                          : HillaireTransmittance(HILLAIRE_INFINITY, viewDir);
#else
    transmittance = TransmittanceFromDepths(vec2(rayleighMs.a, mie.a));
#endif
}

// A pixel no mesh covers (the sky, or the analytic ground its ray meets): linear radiance and
// per-channel transmittance from the sky-view LUT (HILLAIRE_MARCH 0), the march (2), or the two
// blended by uHillaireSpaceWeight (1): the CPU ramps it from 0 at the top of the atmosphere to
// 1 a tenth of its height above, so flying out is continuous.
void HillaireSkyView(vec3 viewDir, out vec3 radiance, out vec3 transmittance) {
#if HILLAIRE_MARCH == 2
    radiance = HillaireMarch(viewDir, HILLAIRE_INFINITY, transmittance).rgb;
#elif HILLAIRE_MARCH == 1
    float w = clamp(uHillaireSpaceWeight, 0.0, 1.0);
    vec3 lutL = vec3(0.0), lutT = vec3(1.0), marchL = vec3(0.0), marchT = vec3(1.0);
    if (w < 1.0) HillaireSkyViewLookup(viewDir, lutL, lutT);
    if (w > 0.0) marchL = HillaireMarch(viewDir, HILLAIRE_INFINITY, marchT).rgb;
    radiance = mix(lutL, marchL, w);
    transmittance = mix(lutT, marchT, w);
#else
    HillaireSkyViewLookup(viewDir, radiance, transmittance);
#endif
}

// HillaireSkyView's radiance alone (the preview and the probes).
vec3 HillaireSkyRadiance(vec3 viewDir) {
    vec3 L, T;
    HillaireSkyView(viewDir, L, T);
    return L;
}

// Per-channel transmittance ([0, 1]) from the camera to distance t (m) along the unit viewDir:
// the ratio of two transmittance-LUT values (Bruneton 2008), along the ray when it misses the
// ground and along the reversed ray otherwise, so both stay in the LUT's domain. Near-horizontal
// rays err up to ~4 % (the ratio of two filtered reads); t ≤ 0 or an empty segment gives 1, a
// zero denominator is floored and the result clamped into [0, 1].
vec3 HillaireTransmittance(float t, vec3 viewDir) {
    float h0 = uHillaireCameraHeight;
    float mu = ClampCosine(dot(viewDir, CameraUp()));
    vec2 seg = HillaireRaySegment(h0, mu, max(t, 0.0));
    if (seg.y <= seg.x) return vec3(1.0);
    // start of the segment (camera, or the entry point from space)
    float r0 = uBottomRadius + h0;
    float hA = HillaireHeightAlong(h0, mu, seg.x);
    float muA = ClampCosine((r0 * mu + seg.x) / (uBottomRadius + hA));
    float hB = HillaireHeightAlong(h0, mu, seg.y);
    float muB = ClampCosine((r0 * mu + seg.y) / (uBottomRadius + hB));
    vec3 T;
    if (HillaireRayHitsGround(h0, mu)) {
        T = HillaireTransmittanceToTop(hB, -muB)
            / max(HillaireTransmittanceToTop(hA, -muA), vec3(HILLAIRE_MIN_TRANSMITTANCE));
    } else {
        T = HillaireTransmittanceToTop(hA, muA)
            / max(HillaireTransmittanceToTop(hB, muB), vec3(HILLAIRE_MIN_TRANSMITTANCE));
    }
    return clamp(T, 0.0, 1.0);
}

// The aerial-perspective volume (Hillaire 2020 §5.4): linear radiance and per-channel
// transmittance to distance dist (m) along the pixel's ray (screenUv for the froxel column, the
// unit viewDir for the phase), from two trilinear reads. Slices are spaced in sqrt(dist), the
// first at range/D² (~125 m); nearer, see below. The alphas and the ozone case are as in
// HillaireSkyViewLookup, except that a segment's highest point is one of its two ends.
void HillaireVolumeLookup(vec2 screenUv, vec3 viewDir, float dist, out vec3 radiance,
                          out vec3 transmittance) {
    float nu = ClampCosine(dot(viewDir, uSunDir));
    float D = float(textureSize(uHillaireApRayleighMs, 0).z);
    float s = D * sqrt(max(dist, 0.0) / uHillaireApRange);   // slice k holds s = k + 1
    vec3 uvw = vec3(screenUv, clamp((max(s, 1.0) - 0.5) / D, 0.5 / D, 1.0 - 0.5 / D));
    vec4 a = texture(uHillaireApRayleighMs, uvw);
    vec4 b = texture(uHillaireApMie, uvw);
    float phaseM = PhaseMieCornetteShanks(nu, uMieG);
    vec3 L = uSunIntensity * (a.rgb + phaseM * b.rgb);
    // Before the first slice (d1 = range / D²): the quadratic through 0 with the camera's own
    // source term as its slope, I(d) = S0 d + (I1 − S0 d1)(d/d1)² — linear fading alone is 10 %
    // low when the density falls fast along the ray (Mie, looking up). It stays ≥ 0 on [0, d1].
    // The density integrals fall linearly to 0 there. Branch-free: x = 1 from the first slice on.
    float d1 = uHillaireApRange / (D * D);
    float x = clamp(dist / d1, 0.0, 1.0);
    vec3 S0 = uSunIntensity * (uHillaireSourceRayleigh * PhaseRayleigh(nu)
                               + uHillaireSourceMie * phaseM + uHillaireSourceMultiple);
    vec3 Lnear = max(S0 * (x * d1) + (L - S0 * d1) * x * x, 0.0);
    radiance = s >= 1.0 ? L : Lnear;
#ifdef HILLAIRE_OZONE
    // the altitude along a line has one minimum, so a segment's highest point is one of its ends
    float h0 = uHillaireCameraHeight;
    float hEnd = HillaireHeightAlong(h0, ClampCosine(dot(viewDir, CameraUp())), dist);
    transmittance = max(h0, hEnd) <= OZONE_BOTTOM ? TransmittanceFromDepths(vec2(a.a, b.a) * x)
                                                  : HillaireTransmittance(dist, viewDir);
#else
    transmittance = TransmittanceFromDepths(vec2(a.a, b.a) * x);
#endif
}

// A mesh at distanceMetres (m) along the pixel's ray: linear radiance and per-channel
// transmittance from the volume (HILLAIRE_MARCH 0), the march (2), or the two blended by
// uHillaireSpaceWeight and over the last 10 % of the volume's range (1). Past the range the
// march alone. distanceMetres ≤ 0 or NaN gives no scattering and T = 1.
void HillaireAerial(vec2 screenUv, vec3 viewDir, float distanceMetres, out vec3 radiance,
                    out vec3 transmittance) {
    radiance = vec3(0.0);
    transmittance = vec3(1.0);
    if (!(distanceMetres > 0.0)) return;
#if HILLAIRE_MARCH == 2
    radiance = HillaireMarch(viewDir, distanceMetres, transmittance).rgb;
#elif HILLAIRE_MARCH == 1
    float range = uHillaireApRange;
    float far = clamp((distanceMetres - HILLAIRE_AP_BLEND_START * range)
                      / (HILLAIRE_AP_BLEND_WIDTH * range), 0.0, 1.0);
    float w = max(clamp(uHillaireSpaceWeight, 0.0, 1.0), far);
    vec3 volL = vec3(0.0), volT = vec3(1.0), marchL = vec3(0.0), marchT = vec3(1.0);
    if (w < 1.0) HillaireVolumeLookup(screenUv, viewDir, distanceMetres, volL, volT);
    if (w > 0.0) marchL = HillaireMarch(viewDir, distanceMetres, marchT).rgb;
    radiance = mix(volL, marchL, w);
    transmittance = mix(volT, marchT, w);
#else
    HillaireVolumeLookup(screenUv, viewDir, distanceMetres, radiance, transmittance);
#endif
}

// HillaireAerial for a mesh pass that knows its fragment's direction: (radiance rgb, mean
// transmittance a); composite as surface · a + rgb.
vec4 HillaireAerialPerspectiveAlongRay(vec2 screenUv, vec3 viewDir, float distanceMetres) {
    vec3 L, T;
    HillaireAerial(screenUv, viewDir, distanceMetres, L, T);
    return vec4(L, HillaireMean(T));
}

// The same along the pixel's own ray, CameraRayDirection(screenUv).
vec4 HillaireAerialPerspective(vec2 screenUv, float distanceMetres) {
    return HillaireAerialPerspectiveAlongRay(screenUv, CameraRayDirection(screenUv),
                                             distanceMetres);
}

// Altitude (m) of a point given relative to the camera (m), without forming |p − C| at planet
// scale (it would cancel in float32); rounding negatives under the root are clamped.
float HillaireHeightOf(vec3 positionRelCamera) {
    float rc = uCameraRadius;
    float along = dot(positionRelCamera, CameraUp());
    float num = 2.0 * rc * along + dot(positionRelCamera, positionRelCamera);  // r² − r_c²
    float r = SafeSqrt(rc * rc + num);
    return uHillaireCameraHeight + num / max(r + rc, 1.0);
}

// Transmittance ([0, 1], rgb) of sunlight reaching a point given relative to the camera (m): 0
// in the planet's shadow. Light a surface with uSunIntensity · this · BRDF · cos.
vec3 HillaireSunTransmittance(vec3 positionRelCamera) {
    float h = HillaireHeightOf(positionRelCamera);
    vec3 n = normalize(positionRelCamera - uEarthCenter);
    return HillaireSunTransmittanceAt(h, ClampCosine(dot(n, uSunDir)));
}
