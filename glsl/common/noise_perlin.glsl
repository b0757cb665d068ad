// Perlin's improved gradient noise, 2D and 3D, plain and periodic.
//
// Source: K. Perlin, "Improving Noise", SIGGRAPH 2002 — cited by the cloud thesis
// (spec/001 §1.1, [35]) as the fix for fully random gradients, and by the maritime thesis
// (spec/000 §1.6) for its Perlin weather map. Numpy twin: app/sim/noise/gradient.py (perlin3,
// perlin2, perlin3_periodic, perlin2_periodic), which reproduces Perlin's reference
// ImprovedNoise to the last bit; the gradient-noise tests compare the two.
//
// The model
// ---------
// Write p = i + f with the lattice cell i = floor(p) and the offset f in [0, 1)^n. Every
// lattice corner c owns a gradient g(c), chosen by hashing c through a permutation P of
// 0..255 (Perlin's chained lookups):
//
//     h(c) = P[(P[(P[c.x mod 256] + c.y) mod 256] + c.z) mod 256]      (2D: two lookups)
//
// The corner contributes the linear ramp g(c) . (p - c), which is zero at the corner, so the
// noise is 0 at every lattice point. The 2^n ramps are blended with the quintic fade
//
//     s(t) = 6 t^5 - 15 t^4 + 10 t^3,    s(0) = 0, s(1) = 1, s' = s'' = 0 at t = 0 and 1,
//
// so value, gradient and second derivatives are continuous across cell faces (the 1985 cubic
// 3t^2 - 2t^3 left s'' discontinuous — visible as creases in bump maps).
//
// Gradients. 3D: the 12 vectors from a cube's centre to its edge midpoints,
// (+-1,+-1,0), (+-1,0,+-1), (0,+-1,+-1), selected by h & 15 with Perlin's bit tests; entries
// 12..15 repeat (1,1,0), (-1,1,0), (0,-1,1), (0,-1,-1), which avoids a division by 12 but
// gives y a slightly larger share: E[g_y^2] = 3/4 against 5/8 for x and z, so an xy slice has
// a few per cent more energy along k_y than along k_x (measured in the tests, within 15%).
// 2D (Perlin gives none; our choice): the 8 directions at 45-degree steps with length sqrt(2),
// g_k = sqrt(2) (cos 45k, sin 45k), selected by h & 7 — symmetric under quarter turns.
//
// Range. Since the fade weights are non-negative, |noise| <= max over the cell of
// sum_c w_c(f) max_g g.(p - c). For the 3D set this is 1.0363538 (at f ~ (0.355, 0.481, 0.5)
// and its mirror images); for the 2D set it is exactly 1 (cell centre, all four gradients
// pointing at it). A given permutation stays below these bounds.
//
// The permutation lives in a texture the application binds (app/render/noise.py,
// GradientNoiseTextures): 256 x 1 R32F, texel i = P[i], read with texelFetch (no filtering).
// Seed None or 0 is Perlin's own table; other seeds are numpy default_rng(seed).permutation.
//
// Failure cases guarded
// ---------------------
// * Negative coordinates: floor() (not int(), which truncates toward zero) gives the cell,
//   and the offset p - floor(p) stays in [0, 1).
// * Huge coordinates: the lattice index is wrapped to [0, 256) (or [0, period)) in floating
//   point before any int conversion, so no int overflow. Precision is the caller's: beyond
//   |p| ~ 2^16 float32 keeps fewer than 8 fractional bits and the noise turns blocky; keep
//   coordinates small and wrap time or offsets modulo 256 (the noise's period) on the CPU.
// * mod() of an integral float by a non power-of-two period rounds: near multiples of the
//   period it may give -1 or period, and beyond |p| ~ 2^24 (where every float is an integer)
//   it is off by up to one float ulp. PerlinWrapIndex takes mod twice (the second on a small
//   integer, exact), fixes the edges with integer compares and clamps, so the index is always
//   in [0, period). Below 2^24 the result is exact and equals the twin's; above it the noise
//   stays finite and bounded but no longer matches the twin (nor means anything: f = 0).
//   The plain noise wraps by 256, a power of two: exact for every float.
// * period < 1 is the caller's error (no meaningful tiling); it is clamped to 1 (noise 0).
//
// Requires GLSL 1.30+ (integer bit operations, texelFetch).

uniform sampler2D uPerlinPermutation;  // 256 x 1, R32F, texel i = P[i] in 0..255

// One lookup in the permutation table; the argument is wrapped into 0..255 first.
int PerlinPermutation(int i) {
    return int(texelFetch(uPerlinPermutation, ivec2(i & 255, 0), 0).r);
}

// s(t) = 6t^5 - 15t^4 + 10t^3, in the reference's Horner order.
float PerlinFade(float t) { return t * t * t * (t * (t * 6.0 - 15.0) + 10.0); }
vec2 PerlinFade(vec2 t) { return t * t * t * (t * (t * 6.0 - 15.0) + 10.0); }
vec3 PerlinFade(vec3 t) { return t * t * t * (t * (t * 6.0 - 15.0) + 10.0); }

// a + t (b - a): the reference's interpolation, written out so the twin can match it.
float PerlinLerp(float t, float a, float b) { return a + t * (b - a); }

// g(h & 15) . d for the 12 (padded to 16) cube-edge gradients, without multiplications.
float PerlinGradient3(int hash, vec3 d) {
    int h = hash & 15;
    float u = h < 8 ? d.x : d.y;
    float v = h < 4 ? d.y : ((h == 12 || h == 14) ? d.x : d.z);
    return ((h & 1) == 0 ? u : -u) + ((h & 2) == 0 ? v : -v);
}

// The 2D gradient set, indexed by h & 7 (app.sim.noise.gradient.GRADIENTS2).
const float PERLIN_SQRT2 = 1.41421356237310;
const vec2 kPerlinGradients2[8] = vec2[8](
    vec2(PERLIN_SQRT2, 0.0), vec2(1.0, 1.0), vec2(0.0, PERLIN_SQRT2), vec2(-1.0, 1.0),
    vec2(-PERLIN_SQRT2, 0.0), vec2(-1.0, -1.0), vec2(0.0, -PERLIN_SQRT2), vec2(1.0, -1.0));

float PerlinGradient2(int hash, vec2 d) { return dot(kPerlinGradients2[hash & 7], d); }

// Euclidean remainder of integral floats by positive ints: floor(p) mod period in
// [0, period). Float mod avoids int overflow; the second mod, the compares and the clamp
// repair its rounding (see the failure cases above).
ivec3 PerlinWrapIndex(vec3 cellFloor, ivec3 period) {
    vec3 r = mod(mod(cellFloor, vec3(period)), vec3(period));
    ivec3 i = ivec3(r);
    i += period * ivec3(lessThan(i, ivec3(0)));
    i -= period * ivec3(greaterThanEqual(i, period));
    return clamp(i, ivec3(0), period - 1);
}

ivec2 PerlinWrapIndex(vec2 cellFloor, ivec2 period) {
    vec2 r = mod(mod(cellFloor, vec2(period)), vec2(period));
    ivec2 i = ivec2(r);
    i += period * ivec2(lessThan(i, ivec2(0)));
    i -= period * ivec2(greaterThanEqual(i, period));
    return clamp(i, ivec2(0), period - 1);
}

// ---- 3D ------------------------------------------------------------------------------------

// The noise of one cell, given the wrapped lattice indices of its low (i0) and high (i1)
// corners and the offset f in [0, 1)^3 — shared by the plain and the periodic noise.
float PerlinNoise3Lattice(ivec3 i0, ivec3 i1, vec3 f) {
    int A = PerlinPermutation(i0.x), B = PerlinPermutation(i1.x);
    int AA = PerlinPermutation(A + i0.y), AB = PerlinPermutation(A + i1.y);
    int BA = PerlinPermutation(B + i0.y), BB = PerlinPermutation(B + i1.y);
    vec3 s = PerlinFade(f);
    vec3 g = f - 1.0;  // offsets from the high corners
    float near = PerlinLerp(s.y,
        PerlinLerp(s.x, PerlinGradient3(PerlinPermutation(AA + i0.z), vec3(f.x, f.y, f.z)),
                        PerlinGradient3(PerlinPermutation(BA + i0.z), vec3(g.x, f.y, f.z))),
        PerlinLerp(s.x, PerlinGradient3(PerlinPermutation(AB + i0.z), vec3(f.x, g.y, f.z)),
                        PerlinGradient3(PerlinPermutation(BB + i0.z), vec3(g.x, g.y, f.z))));
    float far = PerlinLerp(s.y,
        PerlinLerp(s.x, PerlinGradient3(PerlinPermutation(AA + i1.z), vec3(f.x, f.y, g.z)),
                        PerlinGradient3(PerlinPermutation(BA + i1.z), vec3(g.x, f.y, g.z))),
        PerlinLerp(s.x, PerlinGradient3(PerlinPermutation(AB + i1.z), vec3(f.x, g.y, g.z)),
                        PerlinGradient3(PerlinPermutation(BB + i1.z), vec3(g.x, g.y, g.z))));
    return PerlinLerp(s.z, near, far);
}

// Improved noise at p; period 256 on every axis. |value| <= 1.0363538.
float PerlinNoise3(vec3 p) {
    vec3 cell = floor(p);
    ivec3 i0 = ivec3(mod(cell, 256.0)) & 255;  // exact: 256 is a power of two
    return PerlinNoise3Lattice(i0, (i0 + 1) & 255, p - cell);
}

// The same noise with the lattice wrapped modulo `period` (in lattice units): it tiles with
// that period. PerlinNoise3Periodic(p, ivec3(256)) == PerlinNoise3(p).
float PerlinNoise3Periodic(vec3 p, ivec3 period) {
    period = max(period, ivec3(1));
    vec3 cell = floor(p);
    ivec3 i0 = PerlinWrapIndex(cell, period);
    ivec3 i1 = i0 + 1;
    i1 -= period * ivec3(greaterThanEqual(i1, period));
    return PerlinNoise3Lattice(i0, i1, p - cell);
}

// ---- 2D ------------------------------------------------------------------------------------

float PerlinNoise2Lattice(ivec2 i0, ivec2 i1, vec2 f) {
    int A = PerlinPermutation(i0.x), B = PerlinPermutation(i1.x);
    vec2 s = PerlinFade(f);
    vec2 g = f - 1.0;
    return PerlinLerp(s.y,
        PerlinLerp(s.x, PerlinGradient2(PerlinPermutation(A + i0.y), vec2(f.x, f.y)),
                        PerlinGradient2(PerlinPermutation(B + i0.y), vec2(g.x, f.y))),
        PerlinLerp(s.x, PerlinGradient2(PerlinPermutation(A + i1.y), vec2(f.x, g.y)),
                        PerlinGradient2(PerlinPermutation(B + i1.y), vec2(g.x, g.y))));
}

// 2D gradient noise at p (8 gradients, see the header); period 256. |value| <= 1.
float PerlinNoise2(vec2 p) {
    vec2 cell = floor(p);
    ivec2 i0 = ivec2(mod(cell, 256.0)) & 255;
    return PerlinNoise2Lattice(i0, (i0 + 1) & 255, p - cell);
}

float PerlinNoise2Periodic(vec2 p, ivec2 period) {
    period = max(period, ivec2(1));
    vec2 cell = floor(p);
    ivec2 i0 = PerlinWrapIndex(cell, period);
    ivec2 i1 = i0 + 1;
    i1 -= period * ivec2(greaterThanEqual(i1, period));
    return PerlinNoise2Lattice(i0, i1, p - cell);
}
