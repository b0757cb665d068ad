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
// (blended over the last 10 % of the range).
//
// Texture units: six, from first_unit: transmittance, multiple scattering, sky-view ×2,
// aerial perspective ×2.
// Failure cases: a camera/LUT mismatch (the volume was built for another camera: it is drawn
// with the wrong rays), G → ±1 (PhaseMieCornetteShanks clamps), t ≤ 0 (returns 0, T = 1).
// =============================================================================================
#include "hillaire_common.glsl"
#include "skyview.glsl"
#include "camera.glsl"

uniform sampler2D uHillaireSkyViewRayleighMs;   // sky-view target 0
uniform sampler2D uHillaireSkyViewMie;          // sky-view target 1
uniform sampler3D uHillaireApRayleighMs;        // aerial-perspective volume 0
uniform sampler3D uHillaireApMie;               // aerial-perspective volume 1
uniform float uHillaireApRange;                 // m, distance of the last slice
uniform float uHillaireSpaceWeight;             // 0: LUTs valid; 1: per-pixel march only
uniform int uHillaireMarchSteps;                // samples of the fallback march

// (μ, ν, μ_s, cos φ) of a direction, in the camera's local vertical frame.
vec4 HillaireViewAngles(vec3 viewDir) {
    vec3 up = CameraUp();
    float mu = ClampCosine(dot(viewDir, up));
    float muS = ClampCosine(dot(uSunDir, up));
    float nu = ClampCosine(dot(viewDir, uSunDir));
    vec3 vH = viewDir - up * mu;
    vec3 sH = uSunDir - up * muS;
    float lv = length(vH), ls = length(sH);
    float cosPhi = (lv > 1.0e-6 && ls > 1.0e-6) ? dot(vH, sH) / (lv * ls) : 1.0;
    return vec4(mu, nu, muS, ClampCosine(cosPhi));
}

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

vec3 HillaireSkyRadianceFromLut(vec3 viewDir) {
    vec4 a = HillaireViewAngles(viewDir);
    vec2 size = vec2(textureSize(uHillaireSkyViewRayleighMs, 0));
    vec2 uv = HillaireSkyViewUv(a.x, a.w, size, uHillaireCameraHeight);
    vec3 rayleighMs = texture(uHillaireSkyViewRayleighMs, uv).rgb;
    vec3 mie = texture(uHillaireSkyViewMie, uv).rgb;
    return uSunIntensity * (rayleighMs + PhaseMieCornetteShanks(a.y, uMieG) * mie);
}

vec3 HillaireSkyRadiance(vec3 viewDir) {
    float w = clamp(uHillaireSpaceWeight, 0.0, 1.0);
    vec3 lut = vec3(0.0), march = vec3(0.0);
    if (w < 1.0) lut = HillaireSkyRadianceFromLut(viewDir);
    if (w > 0.0) {
        vec3 T;
        march = HillaireMarch(viewDir, HILLAIRE_INFINITY, T).rgb;
    }
    return mix(lut, march, w);
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

// In-scattered radiance per metre at the camera itself (the integrand at t = 0).
vec3 HillaireSourceAtCamera(float mu, float nu, float muS) {
    float h = uHillaireCameraHeight;
    if (h >= HillaireAtmosphereHeight()) return vec3(0.0);
    vec2 density = DensityRM(h);
    vec3 scatR = uBetaRayleigh * density.x, scatM = uBetaMieScatter * density.y;
    vec3 sunT = HillaireSunTransmittanceAt(h, muS);
    return uSunIntensity * (sunT * (scatR * PhaseRayleigh(nu) + scatM * PhaseMieCornetteShanks(nu, uMieG))
                            + uHillaireMsScale * (scatR + scatM) * HillaireMultipleScatteringAt(h, muS));
}

vec4 HillaireAerialPerspectiveFromVolume(vec2 screenUv, vec3 viewDir, float dist) {
    vec4 ang = HillaireViewAngles(viewDir);
    float D = float(textureSize(uHillaireApRayleighMs, 0).z);
    float s = D * sqrt(max(dist, 0.0) / uHillaireApRange);   // slice k holds s = k + 1
    vec3 uvw = vec3(screenUv, clamp((max(s, 1.0) - 0.5) / D, 0.5 / D, 1.0 - 0.5 / D));
    vec4 a = texture(uHillaireApRayleighMs, uvw);
    vec3 mie = texture(uHillaireApMie, uvw).rgb;
    vec3 L = uSunIntensity * (a.rgb + PhaseMieCornetteShanks(ang.y, uMieG) * mie);
    if (s >= 1.0) return vec4(L, a.a);
    // Before the first slice (d1 = range / D²): the quadratic through 0 with the camera's own
    // source term as its slope, I(d) = S0 d + (I1 − S0 d1)(d/d1)² — linear fading alone is 10 %
    // low when the density falls fast along the ray (Mie, looking up). It stays ≥ 0 on [0, d1].
    float d1 = uHillaireApRange / (D * D);
    float x = dist / d1;
    vec3 S0 = HillaireSourceAtCamera(ang.x, ang.y, ang.z);
    vec3 Lnear = max(S0 * dist + (L - S0 * d1) * x * x, 0.0);
    return vec4(Lnear, mix(1.0, a.a, x));
}

vec4 HillaireAerialPerspectiveAlongRay(vec2 screenUv, vec3 viewDir, float distanceMetres) {
    if (!(distanceMetres > 0.0)) return vec4(0.0, 0.0, 0.0, 1.0);
    float range = uHillaireApRange;
    float far = clamp((distanceMetres - 0.9 * range) / (0.1 * range), 0.0, 1.0);
    float w = max(clamp(uHillaireSpaceWeight, 0.0, 1.0), far);
    vec4 vol = vec4(0.0), march = vec4(0.0);
    if (w < 1.0) vol = HillaireAerialPerspectiveFromVolume(screenUv, viewDir, distanceMetres);
    if (w > 0.0) {
        vec3 T;
        march = HillaireMarch(viewDir, distanceMetres, T);
    }
    return mix(vol, march, w);
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
