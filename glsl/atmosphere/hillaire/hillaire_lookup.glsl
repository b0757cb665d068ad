// =============================================================================================
// Method 4 — what a scene's composite pass calls (Hillaire 2020 §5.3 sky-view lookup, §5.4
// aerial-perspective lookup, §4 transmittance, §6 space views). Include this file; bind the LUTs
// with HillaireLuts.bind(program, first_unit) (app/effects/planet/hillaire.py), which also
// sets every uHillaire* uniform below. The scene sets, as for methods 1–3, the model uniforms of
// glsl/atmosphere/model.glsl (uEarthCenter, uCameraRadius, radii, β, H, P0, G, uSunIntensity,
// uSunDir) and the camera uniforms of glsl/common/camera.glsl (uCamRight/Up/Forward,
// uTanHalfFov, uAspect) — the same camera the LUTs were updated with this frame.
//
//   vec3 HillaireSkyRadiance(vec3 viewDir)
//        radiance of a ray that leaves the atmosphere (sun disk NOT included; a ray that hits
//        the ground gets the in-scattering up to the ground);
//   vec4 HillaireAerialPerspective(vec2 screenUv, float distanceMetres)
//        (in-scattered radiance rgb, mean transmittance a) between the camera and a surface at
//        that distance along the pixel's ray CameraRayDirection(screenUv); composite as
//        surface · a + rgb, or per channel with HillaireTransmittance;
//   vec4 HillaireAerialPerspectiveAlongRay(vec2 screenUv, vec3 viewDir, float distanceMetres)
//        the same with the ray given (a mesh pass that knows its fragment's direction);
//   vec3 HillaireTransmittance(float t, vec3 viewDir)
//        per-channel transmittance from the camera to distance t (transmittance-LUT ratio);
//   void HillaireSkyView(vec3 viewDir, out vec3 radiance, out vec3 transmittance)
//        a pixel no mesh covers (the sky, or the analytic ground the ray meets): the sky-view
//        LUT's radiance and per-channel transmittance of the whole ray (to the top or the
//        ground), two bilinear reads;
//   void HillaireAerial(vec2 screenUv, vec3 viewDir, float distanceMetres, out vec3 radiance,
//                       out vec3 transmittance)
//        a mesh at that distance: the volume's radiance and per-channel transmittance, two
//        trilinear reads. These two are the per-pixel pass of Hillaire's paper: lookups only.
//   vec3 HillaireSunTransmittance(vec3 positionRelCamera)
//        transmittance of sunlight reaching a point (0 in the planet's shadow): light a surface
//        with uSunIntensity · HillaireSunTransmittance(p) · BRDF · cos.
//
// Units: radiance = uSunIntensity × dimensionless integrals, as in model.glsl; uSunIntensity is
// used as a sun *illuminance* E (radiance = E · σ · phase per steradian · length), exactly as in
// the thesis's in-scattering integral (spec/002 §1.5), so method 4 with uHillaireMsScale = 0
// converges to method 1 as its steps grow.
//
// Space and far distances (Hillaire §6): above the top of the atmosphere the sky-view LUT and
// the volume are replaced by a per-pixel march of the same integral with the transmittance and
// multiple-scattering LUTs (uHillaireMarchSteps samples); the weight uHillaireSpaceWeight (set
// by the CPU) ramps from 0 at the top to 1 a tenth of the atmosphere's height above it, so
// flying out is continuous. Past uHillaireApRange the volume hands over to the same march
// (blended over the last 10 % of the range). HILLAIRE_MARCH says at compile time which of them
// a program contains: 1 (the default) both, chosen per pixel as above; 0 the lookups alone (the
// camera inside the atmosphere, every mesh within the range: what the scene's pass compiles in
// the usual case); 2 the march alone (the camera above the blend band). A software rasteriser
// runs every branch a program contains, so the march must be compiled out, not skipped.
//
// What the LUTs store (skyview_lut.frag, aerial_perspective.glsl): rgb the phase-free Mie and
// the phased Rayleigh + multiple scattering integrals, and in their alphas the density
// integrals (∫ρ_R dt, ∫ρ_M dt) of the same ray, so that the per-channel transmittance is
// exp(−(β^ext_R x + β^ext_M y)) from the same two reads (model.glsl's TransmittanceFromDepths).
// The ozone layer (model.glsl, beyond the thesis) adds a third density integral the alphas have
// no room for: with HILLAIRE_OZONE defined (the scene defines it when the layer is on) the
// per-channel transmittance of a sky-view or volume lookup whose segment rises into the layer
// (above 10 km) comes instead from the transmittance LUT, which includes ozone (HillaireTransmittance:
// one read to the top, or the ratio of two); a segment that stays below the layer keeps the
// alphas' exact value (the LUT ratio errs up to ~4 % on near-horizontal rays).
// The volume's first slice lies range/D² from the camera; nearer (a mesh within ~125 m), the
// radiance follows the quadratic through 0 whose slope is the camera's own source term, whose
// per-frame factors (sunlight × σ_R, sunlight × σ_M, σ_s Ψ_ms at the camera) come from the CPU
// (uHillaireSource*, HillaireLuts.lookup_uniforms), and the density integrals fall linearly.
//
// Texture units: six: transmittance, multiple scattering, sky-view ×2, aerial perspective ×2.
// Failure cases: a camera/LUT mismatch (the volume was built for another camera: it is drawn
// with the wrong rays), G → ±1 (PhaseMieCornetteShanks clamps), t ≤ 0 (returns 0, T = 1).
// =============================================================================================
#include "hillaire_common.glsl"
#include "skyview.glsl"
#include "camera.glsl"

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

// (μ, ν, μ_s, cos φ) of a direction, in the camera's local vertical frame.
vec4 HillaireViewAngles(vec3 viewDir) {
    vec3 up = CameraUp();
    float mu = ClampCosine(dot(viewDir, up));
    float muS = ClampCosine(dot(uSunDir, up));
    float nu = ClampCosine(dot(viewDir, uSunDir));
    // cos φ between the horizontal parts v − μ up and s − μ_s up, from the cosines alone:
    // (ν − μ μ_s) / sqrt((1 − μ²)(1 − μ_s²)) — no vectors formed per pixel (1 when either is
    // vertical, where φ is undefined and the sky-view LUT does not depend on it)
    float d = (1.0 - mu * mu) * (1.0 - muS * muS);
    float cosPhi = d > 1.0e-12 ? (nu - mu * muS) * inversesqrt(d) : 1.0;
    return vec4(mu, nu, muS, ClampCosine(cosPhi));
}

vec3 HillaireTransmittance(float t, vec3 viewDir);

// The same integral as the LUTs, marched for one pixel from the camera (or the entry point).
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

// The sky-view LUT for the ray along viewDir: radiance (no sun disk) and the per-channel
// transmittance of the whole ray, to the top of the atmosphere or to the ground.
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

vec3 HillaireSkyRadianceFromLut(vec3 viewDir) {
    vec3 L, T;
    HillaireSkyViewLookup(viewDir, L, T);
    return L;
}

// A pixel no mesh covers: the sky-view LUT (HILLAIRE_MARCH 0), the march (2), or the two blended
// by uHillaireSpaceWeight (1).
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

vec3 HillaireSkyRadiance(vec3 viewDir) {
    vec3 L, T;
    HillaireSkyView(viewDir, L, T);
    return L;
}

// Per-channel transmittance from the camera to distance t along viewDir: the ratio of two
// transmittance-LUT values (Bruneton 2008), taken along the ray's direction when it does not
// hit the ground, and along the reversed ray otherwise (both then stay in the LUT's domain).
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
        T = HillaireTransmittanceToTop(hB, -muB) / max(HillaireTransmittanceToTop(hA, -muA), vec3(1.0e-30));
    } else {
        T = HillaireTransmittanceToTop(hA, muA) / max(HillaireTransmittanceToTop(hB, muB), vec3(1.0e-30));
    }
    return clamp(T, 0.0, 1.0);
}

// In-scattered radiance per metre at the camera itself (the integrand at t = 0), from the
// per-frame factors the CPU sets (0 above the top of the atmosphere).
vec3 HillaireSourceAtCamera(float nu) {
    return uSunIntensity * (uHillaireSourceRayleigh * PhaseRayleigh(nu)
                            + uHillaireSourceMie * PhaseMieCornetteShanks(nu, uMieG)
                            + uHillaireSourceMultiple);
}

// The volume's radiance and per-channel transmittance to distance dist along the pixel's ray
// (screenUv for the froxel column, viewDir for the Mie phase): two trilinear reads.
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

vec4 HillaireAerialPerspectiveFromVolume(vec2 screenUv, vec3 viewDir, float dist) {
    vec3 L, T;
    HillaireVolumeLookup(screenUv, viewDir, dist, L, T);
    return vec4(L, HillaireMean(T));
}

// A mesh at distanceMetres along the pixel's ray: the volume (HILLAIRE_MARCH 0), the march (2),
// or the two blended by uHillaireSpaceWeight and past 90 % of the volume's range (1).
void HillaireAerial(vec2 screenUv, vec3 viewDir, float distanceMetres, out vec3 radiance,
                    out vec3 transmittance) {
    radiance = vec3(0.0);
    transmittance = vec3(1.0);
    if (!(distanceMetres > 0.0)) return;
#if HILLAIRE_MARCH == 2
    radiance = HillaireMarch(viewDir, distanceMetres, transmittance).rgb;
#elif HILLAIRE_MARCH == 1
    float range = uHillaireApRange;
    float far = clamp((distanceMetres - 0.9 * range) / (0.1 * range), 0.0, 1.0);
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

vec4 HillaireAerialPerspectiveAlongRay(vec2 screenUv, vec3 viewDir, float distanceMetres) {
    vec3 L, T;
    HillaireAerial(screenUv, viewDir, distanceMetres, L, T);
    return vec4(L, HillaireMean(T));
}

vec4 HillaireAerialPerspective(vec2 screenUv, float distanceMetres) {
    return HillaireAerialPerspectiveAlongRay(screenUv, CameraRayDirection(screenUv), distanceMetres);
}

// Altitude of a point given relative to the camera, without forming |p − C| at planet scale.
float HillaireHeightOf(vec3 positionRelCamera) {
    float rc = uCameraRadius;
    float along = dot(positionRelCamera, CameraUp());
    float num = 2.0 * rc * along + dot(positionRelCamera, positionRelCamera);  // r² − r_c²
    float r = SafeSqrt(rc * rc + num);
    return uHillaireCameraHeight + num / max(r + rc, 1.0);
}

vec3 HillaireSunTransmittance(vec3 positionRelCamera) {
    float h = HillaireHeightOf(positionRelCamera);
    vec3 n = normalize(positionRelCamera - uEarthCenter);
    return HillaireSunTransmittanceAt(h, ClampCosine(dot(n, uSunDir)));
}
