// =============================================================================================
// Single scattering along a view segment — the thesis's in-scattering integral (spec/002 §1.5)
//   Color_in = ∫ I_sun · e^(−τ(AP)) · e^(−τ(PC)) · V(P)
//              · (β_R ρ_R(h) P_R(θ) + β_M ρ_M(h) P_M(θ)) ds
// as a midpoint Riemann sum over N_STEPS (§1.7: s = 0.5 … N − 0.5), with τ(PC) accumulated along
// the outer loop (to the sample's midpoint; the thesis's code adds the whole current step — a
// switch, uThesisPcRule, keeps that rule: on by default for method 1 only, whose figure it
// makes, see planet/composite.frag) and τ(AP), the depth
// toward the sun, from one of:
//   SUN_DEPTH_BRUTE_FORCE  a nested midpoint sum to the top of the atmosphere (first approximation)
//   SUN_DEPTH_LUT          the optical-depth ("Chapman") lookup table (second approximation)
// and V(P) from the shadow map when SHADOWED_INSCATTER is defined (final approximation).
// Errata fixed: transmittance is e^(−τ) (§1.4 printed ×τ); the Earth normal is normalize(P − C)
// (§2.3's precedence bug); the Rayleigh scattering coefficient is β^scatt_R (§2.2's betaSR typo);
// P0 scales the density in both loops (the printed inner loop dropped it).
// A sample whose sun ray hits the planet gets no sunlight (the planet's shadow).
// =============================================================================================

uniform int uSteps;        // N_STEPS (30 in the thesis)
uniform bool uThesisPcRule;   // τ(PC) includes the whole current step (the thesis's code), not half
uniform int uInnerSteps;   // inner steps of the brute-force sun integral

// Density integral from P (camera-relative) toward the sun to the top of the atmosphere, by a
// midpoint sum; a huge value when the sun ray hits the planet.
vec2 SunDepthBruteForce(vec3 P) {
    vec2 ground, top;
    if (RaySphereIntersect(P, uSunDir, uEarthCenter, uBottomRadius, ground) && ground.x > 0.0) {
        return vec2(1.0e12);
    }
    RaySphereIntersect(P, uSunDir, uEarthCenter, uTopRadius, top);
    float len = top.y;
    if (len <= 0.0) return vec2(0.0);
    vec3 rel = P - uEarthCenter;
    float r = length(rel);
    float mu = dot(rel, uSunDir) / r;
    float ds = len / float(uInnerSteps);
    vec2 depth = vec2(0.0);
    for (int i = 0; i < 4096; ++i) {
        if (i >= uInnerSteps) break;
        float s = (float(i) + 0.5) * ds;
        float h = SafeSqrt(s * s + 2.0 * r * mu * s + r * r) - uBottomRadius;
        depth += DensityRM(h) * ds;
    }
    return depth;
}

#ifdef SUN_DEPTH_LUT
vec2 SunDepth(vec3 P, float h) {
    vec3 normalEarth = normalize(P - uEarthCenter);
    return OpticalDepthToSun(h, dot(normalEarth, uSunDir));
}
#else
vec2 SunDepth(vec3 P, float h) { return SunDepthBruteForce(P); }
#endif

// In-scattered radiance along dir over [t0, t1]; depthPC returns the camera→end density integral.
vec3 InScatter(vec3 dir, float t0, float t1, out vec2 depthPC) {
    depthPC = vec2(0.0);
    if (t1 <= t0) return vec3(0.0);
    float mu = dot(dir, CameraUp());
    float ds = (t1 - t0) / float(uSteps);
    vec3 rayleigh = vec3(0.0), mie = vec3(0.0);
    for (int i = 0; i < 4096; ++i) {
        if (i >= uSteps) break;
        float t = t0 + (float(i) + 0.5) * ds;
        vec3 P = dir * t;
        float h = HeightAlongRay(t, mu);
        // No air above the top of the atmosphere (§2.4: samples outside it have zero density);
        // only the unclipped method 1 has such samples, which otherwise add a glow beyond the limb.
        vec2 rho = h > uTopRadius - uBottomRadius ? vec2(0.0) : DensityRM(h);
        vec2 depthAP = SunDepth(P, h);
        // τ(PC) to the sample: the thesis adds the whole current step first, which overstates it by
        // half a step (≈ 50 % error on the horizon at N = 30); the midpoint rule adds half of it.
        vec2 toSample = depthPC + rho * ds * (uThesisPcRule ? 1.0 : 0.5);
        depthPC += rho * ds;
        vec3 ext = TransmittanceFromDepths(depthAP + toSample);
        float visibility = 1.0;
#ifdef SHADOWED_INSCATTER
        visibility = ShadowVisibilityPoint(P + uCameraLocal);
#endif
        rayleigh += rho.x * ext * ds * visibility;
        mie += rho.y * ext * ds * visibility;
    }
    float cosTheta = dot(dir, uSunDir);
    return (rayleigh * uBetaRayleigh * PhaseRayleigh(cosTheta)
            + mie * uBetaMieScatter * PhaseMieCornetteShanks(cosTheta, uMieG)) * uSunIntensity;
}
