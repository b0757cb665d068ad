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
// Beyond the thesis: the ozone layer (model.glsl, 0 there) is the third component of every
// density integral (vec3 (R, M, O)); it absorbs and scatters nothing.
// =============================================================================================

uniform int uSteps;        // N_STEPS (30 in the thesis)
uniform bool uThesisPcRule;   // τ(PC) includes the whole current step (the thesis's code), not half
uniform int uInnerSteps;   // inner steps of the brute-force sun integral

// Density integral from P (camera-relative) toward the sun to the top of the atmosphere, by a
// midpoint sum; a huge value when the sun ray hits the planet.
vec3 SunDepthBruteForce(vec3 P) {
    vec2 ground, top;
    if (RaySphereIntersect(P, uSunDir, uEarthCenter, uBottomRadius, ground) && ground.x > 0.0) {
        return vec3(1.0e12);
    }
    RaySphereIntersect(P, uSunDir, uEarthCenter, uTopRadius, top);
    float len = top.y;
    if (len <= 0.0) return vec3(0.0);
    vec3 rel = P - uEarthCenter;
    float r = length(rel);
    float mu = dot(rel, uSunDir) / r;
    float ds = len / float(uInnerSteps);
    vec3 depth = vec3(0.0);
    for (int i = 0; i < uInnerSteps; ++i) {
        float s = (float(i) + 0.5) * ds;
        float h = SafeSqrt(s * s + 2.0 * r * mu * s + r * r) - uBottomRadius;
        depth += DensityRMO(h) * ds;
    }
    return depth;
}

#ifdef SUN_DEPTH_LUT
// τ(AP) from the LUT at height h with the sun at cos Φ to the local vertical (the position is not
// needed: cos Φ comes from the ray's own geometry, see InScatterSteps).
vec3 SunDepth(vec3 P, float h, float cosPhi) { return OpticalDepthToSun(h, cosPhi); }
#else
vec3 SunDepth(vec3 P, float h, float cosPhi) { return SunDepthBruteForce(P); }
#endif

// The running sums of the in-scattering integral along one view ray.
struct InScatterSums {
    vec3 depthPC;    // density integrals (R, M, O) camera → the current position
    vec3 rayleigh;   // Σ ρ_R e^(−τ) V ds
    vec3 mie;        // Σ ρ_M e^(−τ) V ds
};

// Samples first … last − 1 (s = i + 0.5 of uSteps) of the midpoint sum on dir from t0, in order.
// cos Φ at a sample, the sun's angle to its local vertical, is (r_c μ_s + t ν) / r along the ray
// (r_c the camera's radius, μ_s the sun's cosine to the camera's vertical, ν the view–sun
// cosine): the same as normalize(P − C) · sun without forming planet-scale differences.
// `shadowed` (a constant at each call) adds V(P) from the shadow map; the caller passes it only
// for the samples ShadowSampleRange says may be in shadow — V ≡ 1 elsewhere, exactly (see
// planet/shadow.glsl) — so samples far from the casters pay no shadow-map read.
void InScatterSteps(inout InScatterSums acc, vec3 dir, float mu, float muS, float nu, float t0,
                    float ds, int first, int last, bool shadowed) {
    for (int i = first; i < last; ++i) {
        float t = t0 + (float(i) + 0.5) * ds;
        vec3 P = dir * t;
        float h = HeightAlongRay(t, mu);
        // No air above the top of the atmosphere (§2.4: samples outside it have zero density);
        // only the unclipped method 1 has such samples, which otherwise add a glow beyond the limb.
        vec3 rho = h > uTopRadius - uBottomRadius ? vec3(0.0) : DensityRMO(h);
        vec3 depthAP = SunDepth(P, h, (uCameraRadius * muS + t * nu) / (uBottomRadius + h));
        // τ(PC) to the sample: the thesis adds the whole current step first, which overstates it by
        // half a step (≈ 50 % error on the horizon at N = 30); the midpoint rule adds half of it.
        vec3 toSample = acc.depthPC + rho * ds * (uThesisPcRule ? 1.0 : 0.5);
        acc.depthPC += rho * ds;
        vec3 ext = TransmittanceFromDepths(depthAP + toSample) * ds;
#ifdef SHADOWED_INSCATTER
        if (shadowed) ext *= ShadowVisibilityPoint(P + uCameraLocal);
#endif
        acc.rayleigh += rho.x * ext;
        acc.mie += rho.y * ext;
    }
}

// In-scattered radiance along dir over [t0, t1] by an `steps`-sample midpoint sum; depthPC
// returns the camera→end density integral. steps = 0 runs no loop at all (a pixel that need not
// march: on a software rasteriser the loops then stop for a block where no pixel marches).
vec3 InScatterN(vec3 dir, float t0, float t1, int steps, out vec3 depthPC) {
    depthPC = vec3(0.0);
    if (t1 <= t0) return vec3(0.0);
    vec3 up = CameraUp();
    float mu = dot(dir, up);
    float muS = dot(uSunDir, up);
    float cosTheta = dot(dir, uSunDir);
    int n = clamp(steps, 0, 4096);
    float ds = n > 0 ? (t1 - t0) / float(n) : 0.0;   // 0: no sample, no shadow range
    InScatterSums acc = InScatterSums(vec3(0.0), vec3(0.0), vec3(0.0));
#ifdef SHADOWED_INSCATTER
    // three runs of the same sum in the same order: V read only where a caster may hide the sun
    ivec2 shadowed = ShadowSampleRange(uCameraLocal, dir, t0, ds, n);
    InScatterSteps(acc, dir, mu, muS, cosTheta, t0, ds, 0, shadowed.x, false);
    InScatterSteps(acc, dir, mu, muS, cosTheta, t0, ds, shadowed.x, shadowed.y, true);
    InScatterSteps(acc, dir, mu, muS, cosTheta, t0, ds, shadowed.y, n, false);
#else
    InScatterSteps(acc, dir, mu, muS, cosTheta, t0, ds, 0, n, false);
#endif
    depthPC = acc.depthPC;
    return (acc.rayleigh * uBetaRayleigh * PhaseRayleigh(cosTheta)
            + acc.mie * uBetaMieScatter * PhaseMieCornetteShanks(cosTheta, uMieG)) * uSunIntensity;
}

// In-scattered radiance along dir over [t0, t1] with N_STEPS = uSteps samples.
vec3 InScatter(vec3 dir, float t0, float t1, out vec3 depthPC) {
    return InScatterN(dir, t0, t1, uSteps, depthPC);
}
