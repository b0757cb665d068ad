// =============================================================================================
// Global fog of every lit surface (spec/003 §2.11 b: the thesis's UNITY_CALC_FOG_FACTOR_RAW in
// the ForwardBase pass, FogGenerator.cs driving it), and beyond the thesis an analytic
// exponential height fog (Quílez, "Better fog", 2010). A surface shader includes this file,
// computes the factor in its vertex stage and applies it once per fragment, after its lighting:
//
//   vertex    vWorldPos = vec4(world.xyz, FogVertexFactor(gl_Position));   (the factor rides in
//             the w of the world-position interpolator, as the thesis packs it: no extra varying)
//   fragment  colour = FogApply(colour, vWorldPos.w, vWorldPos.xyz);
//
// The distance without a square root, from the clip position (the thesis's trick):
//   Unity's clip z runs from near (at the near plane) to 0 (at the far plane) — a reversed-Z
//   D3D projection; from GL's clip w (the view depth w): z_u = n·(f − w)/(f − n). Then
//   d = max(f·(1 − z_u/n), 0)                                  spec/003 eq. 7.24
//   so z_u = 0 gives d = f                                     spec/003 eq. 7.25
//   and z_u = n gives d = 0: distances start at the near plane spec/003 eq. 7.26
//   (d = f·(w − n)/(f − n), the planar depth past the near plane, stretched by f/(f − n)).
// The factor f(d) (1 = no fog, 0 = all fog; "it decreases with distance, so the colours are
// swapped in the lerp": colour = lerp(fogColour, colour, f)):
//   linear  f = (e − d)/(e − s)                                spec/003 eq. 7.27
//   exp     f = exp(−t·d)                                      spec/003 eq. 7.28
//   exp2    f = exp(−(t·d)²)                                   spec/003 eq. 7.29
//   i = 1 − f is the fog's intensity i = f(d, t) of           spec/003 eq. 7.23
// uFogPerPixel (beyond the thesis): the factor is recomputed per fragment from 1/gl_FragCoord.w
// (the same planar depth), instead of interpolated from the vertices — exact on large
// triangles, where the per-vertex exponential is interpolated linearly (the bench charts the
// error). uFogHeight (beyond the thesis, Quílez 2010): density ρ(y) = a·exp(−b·(y − y0))
// integrated exactly along the camera ray o → p of length t; y runs linearly along it, so with
// e_i = −b·(y_i − y0) at its two ends
//   τ = a·t·(e^e0 − e^e1)/(e0 − e1) = a·t·e^m·(1 − e^(−u))/u,  m = max(e0, e1), u = |e0 − e1|
// (Quílez's a·e^(−b·o_y)·(1 − e^(−b·d_y·t))/(b·d_y), written around the denser end), f = e^(−τ);
// it replaces the distance fog when on.
//
// Failure cases guarded: e = s in the linear mode (a division by zero) — the factor is then a
// step at s; every factor clamped to [0, 1] (Unity saturates it; the linear one is negative past
// e and above 1 before s); a near plane of 0 (z_u/n) is kept at 1e-6; w ≤ 0 (a vertex behind
// the camera) gives d = 0, not a negative distance. The height fog: the grazing ray (u → 0, the
// 0/0 of Quílez's form) uses the series 1 − u/2 + u²/6 of (1 − e^(−u))/u below u < 1e-2 (fp32
// cancels there); no division by t or d_y at all (t = 0 gives τ = 0); a camera high above the
// fog looking down a long ray cannot overflow (the exponent is taken at the denser end, so
// (1 − e^(−u))/u ≤ 1 and only e^m grows); a·e^m is exp(ln a + m) clamped at 60 (e^60 ≈ 1e26,
// still finite times any distance and density), so a camera far below y0 sees opaque fog
// rather than inf·0; b = 0 is a uniform fog (τ = a·t), a = 0 no fog.
// Numpy twin: app/sim/fog.py (same names in snake case).
// =============================================================================================

// uFogMode: 0 off, 1 linear, 2 exp, 3 exp2 (Unity's FOG_LINEAR / FOG_EXP / FOG_EXP2)
uniform int uFogMode;
uniform vec3 uFogParams;       // (density t, start s, end e): unity_FogParams
uniform vec3 uFogColor;        // linear radiance of the fog
uniform vec2 uFogNearFar;      // the camera's near and far planes [m]
uniform bool uFogPerPixel;     // the factor per fragment instead of per vertex
uniform bool uFogHeight;       // analytic exponential height fog instead of the distance fog
uniform vec3 uFogHeightParams; // (a density at y0 [1/m], b falloff [1/m], y0 [m])
uniform vec3 uFogCameraPos;    // world position of the camera (the height fog's ray origin)

// spec/003 eq. 7.24: the distance past the near plane from Unity's clip z, z_u (GL's view
// depth w given, z_u = n·(f − w)/(f − n)); spec/003 eq. 7.25 and spec/003 eq. 7.26 are its ends.
float FogUnityClipZ(float w, vec2 nearFar) {
    float n = max(nearFar.x, 1e-6), f = max(nearFar.y, n + 1e-6);
    return n * (f - w) / (f - n);
}
float FogDistance(float w, vec2 nearFar) {
    float n = max(nearFar.x, 1e-6), f = max(nearFar.y, n + 1e-6);
    return max(f * (1.0 - FogUnityClipZ(max(w, 0.0), nearFar) / n), 0.0);
}

// spec/003 eq. 7.27: Unity's linear factor (e − d)/(e − s), a step at s when e = s.
float FogFactorLinear(float d, float start, float end) {
    float span = end - start;
    if (abs(span) < 1e-6) return d < start ? 1.0 : 0.0;
    return clamp((end - d) / span, 0.0, 1.0);
}

// spec/003 eq. 7.28: exp(−t·d).
float FogFactorExp(float d, float density) { return clamp(exp(-density * d), 0.0, 1.0); }

// spec/003 eq. 7.29: exp(−(t·d)²).
float FogFactorExp2(float d, float density) {
    float x = density * d;
    return clamp(exp(-x * x), 0.0, 1.0);
}

// The mode's factor at distance d (spec/003 eq. 7.23: the intensity is 1 − this); 1 when off.
float FogFactor(float d) {
    if (uFogMode == 1) return FogFactorLinear(d, uFogParams.y, uFogParams.z);
    if (uFogMode == 2) return FogFactorExp(d, uFogParams.x);
    if (uFogMode == 3) return FogFactorExp2(d, uFogParams.x);
    return 1.0;
}

// (1 − e^(−x))/x, with its series below |x| < 1e-2 (fp32's 1 − e^(−x) cancels there).
float FogOneMinusExpOverX(float x) {
    if (abs(x) < 1e-2) return 1.0 - 0.5 * x + x * x / 6.0;
    return (1.0 - exp(-x)) / x;
}

// Quílez 2010: the optical depth of the exponential height fog from the camera to p, around
// the denser end (see the header).
float FogHeightOpticalDepth(vec3 p) {
    float a = uFogHeightParams.x, b = max(uFogHeightParams.y, 0.0), y0 = uFogHeightParams.z;
    if (a <= 0.0) return 0.0;
    float t = length(p - uFogCameraPos);
    float e0 = -b * (uFogCameraPos.y - y0), e1 = -b * (p.y - y0);
    float dens = exp(min(log(a) + max(e0, e1), 60.0));
    return dens * t * FogOneMinusExpOverX(abs(e0 - e1));
}

// Quílez 2010: the transmittance exp(−τ) of the exponential height fog from the camera to p.
float FogHeightTransmittance(vec3 p) {
    return clamp(exp(-FogHeightOpticalDepth(p)), 0.0, 1.0);
}

// The factor of a vertex, from its clip position (the thesis's per-vertex fog; 1 when off, and
// unused by the height fog and the per-pixel path, which the fragment computes itself).
float FogVertexFactor(vec4 clipPos) {
    if (uFogMode == 0 || uFogHeight) return 1.0;
    return FogFactor(FogDistance(clipPos.w, uFogNearFar));
}

#ifdef NATURA_FRAGMENT_STAGE
// After the lighting: lerp(fogColour, colour, f) with the per-vertex f, or the per-fragment one,
// or the height fog's transmittance. Fragment stages only (gl_FragCoord: the library defines
// NATURA_FRAGMENT_STAGE there).
vec3 FogApply(vec3 colour, float vertexFactor, vec3 worldPos) {
    if (uFogHeight) return mix(uFogColor, colour, FogHeightTransmittance(worldPos));
    if (uFogMode == 0) return colour;
    float f = uFogPerPixel ? FogFactor(FogDistance(1.0 / gl_FragCoord.w, uFogNearFar))
                           : clamp(vertexFactor, 0.0, 1.0);
    return mix(uFogColor, colour, f);
}
#endif
