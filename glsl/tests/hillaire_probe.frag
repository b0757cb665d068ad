#version 330 core
// Test probe for method 4 (used by the Hillaire tests): evaluates the lookups of
// glsl/atmosphere/hillaire/hillaire_lookup.glsl per pixel of a small target, and a brute-force
// reference of the same integral — uniform midpoint steps on the view ray, a nested midpoint
// march toward the sun for T_sun (no transmittance LUT), the multiple-scattering source from the
// Ψ_ms LUT — so a test can compare the LUT path with it.
//   uProbeMode 0: HillaireSkyRadiance(dir)                         rgb
//              1: HillaireAerialPerspective(uv, uProbeDistance)    rgb, a = mean T
//              2: HillaireTransmittance(uProbeDistance, dir)       rgb
//              3: HillaireSunTransmittance(dir · uProbeDistance)   rgb
//              4: brute force to the top / ground                  rgb, a = mean T
//              5: brute force to uProbeDistance                    rgb, a = mean T
//              6: HillaireMarch to uProbeDistance (the fallback)   rgb, a = mean T
#include "../atmosphere/hillaire/hillaire_lookup.glsl"

in vec2 vUV;
out vec4 fragColor;
uniform int uProbeMode;
uniform float uProbeDistance;
uniform int uProbeSteps;      // view-ray steps of the brute force
uniform int uProbeSunSteps;   // sun-ray steps of the brute force

// T_sun by a midpoint march to the top of the atmosphere (uProbeSunSteps steps, denser near
// the point: s³ spacing), at height h above the ground (the LUTs' length unit) and sun cosine
// muS; 0 where the ground hides the sun. The reference for the transmittance LUT.
vec3 ProbeSunTransmittance(float h, float muS) {
    if (HillaireRayHitsGround(h, muS)) return vec3(0.0);
    float d = HillaireDistanceToTop(h, muS);
    float n = float(uProbeSunSteps);
    vec2 depth = vec2(0.0);
    for (int i = 0; i < uProbeSunSteps; ++i) {
        float s = (float(i) + 0.5) / n;
        depth += DensityRM(HillaireHeightAlong(h, muS, d * s * s * s)) * (3.0 * d * s * s / n);
    }
    return TransmittanceFromDepths(depth);
}

// The brute-force sky along dir up to maxDist: uProbeSteps midpoint steps of single
// scattering (ProbeSunTransmittance for T_sun) plus the Ψ_ms LUT's multiple scattering;
// rgb the radiance, a the mean transmittance. A ray with an empty segment returns (0, 1).
vec4 ProbeBruteForce(vec3 dir, float maxDist) {
    vec4 a = HillaireViewAngles(dir);
    float mu = a.x, nu = a.y, muS = a.z;
    float h0 = uHillaireCameraHeight;
    vec2 seg = HillaireRaySegment(h0, mu, maxDist);
    if (seg.y <= seg.x) return vec4(0.0, 0.0, 0.0, 1.0);
    float dt = (seg.y - seg.x) / float(uProbeSteps);
    vec3 depth = vec3(0.0), L = vec3(0.0);
    float r0 = uBottomRadius + h0;
    for (int i = 0; i < uProbeSteps; ++i) {
        float t = seg.x + (float(i) + 0.5) * dt;
        float h = HillaireHeightAlong(h0, mu, t);
        vec2 rho = DensityRM(h);
        vec3 sR = uBetaRayleigh * rho.x, sM = uBetaMieScatter * rho.y;
        vec3 step_ = (uBetaRayleigh * rho.x + uBetaMieExt * rho.y) * dt;
        vec3 T = exp(-(depth + 0.5 * step_));
        float muSAt = ClampCosine((r0 * muS + t * nu) / (uBottomRadius + max(h, 0.0)));
        vec3 sun = ProbeSunTransmittance(h, muSAt);
        L += T * (sun * (sR * PhaseRayleigh(nu) + sM * PhaseMieCornetteShanks(nu, uMieG))
                  + uHillaireMsScale * (sR + sM) * HillaireMultipleScatteringAt(h, muSAt)) * dt;
        depth += step_;
    }
    return vec4(uSunIntensity * L, HillaireMean(exp(-depth)));
}

void main() {
    vec2 uv = vUV;
    vec3 dir = CameraRayDirection(uv);
    vec3 T;
    if (uProbeMode == 0) fragColor = vec4(HillaireSkyRadiance(dir), 0.0);
    else if (uProbeMode == 1) fragColor = HillaireAerialPerspective(uv, uProbeDistance);
    else if (uProbeMode == 2) fragColor = vec4(HillaireTransmittance(uProbeDistance, dir), 0.0);
    else if (uProbeMode == 3) fragColor = vec4(HillaireSunTransmittance(dir * uProbeDistance), 0.0);
    else if (uProbeMode == 4) fragColor = ProbeBruteForce(dir, HILLAIRE_INFINITY);
    else if (uProbeMode == 5) fragColor = ProbeBruteForce(dir, uProbeDistance);
    else fragColor = HillaireMarch(dir, uProbeDistance, T);
}
