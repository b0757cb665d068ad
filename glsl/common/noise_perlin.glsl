// Perlin's improved gradient noise, 2D and 3D, plain and periodic (Perlin 2002, "Improving
// Noise"), cited by the cloud thesis (spec/001 §1.1, [35]) as the fix for fully random
// gradients and by the maritime thesis (spec/000 §1.6) for its Perlin weather map. Numpy twin:
// app/sim/noise/gradient.py (perlin3, perlin2, perlin3_periodic, perlin2_periodic), which
// reproduces Perlin's reference ImprovedNoise to the last bit; the gradient-noise tests compare
// the two. The 3D gradients are 12 padded to 16 entries, which gives y a few per cent more
// energy (PerlinGradient3). Failure cases guarded, each at its function: negative and huge
// coordinates, the rounding of a float mod by a period, a period below 1. Precision is the
// caller's: beyond |p| ~ 2^16 float32 keeps fewer than 8 fractional bits and the noise turns
// blocky; keep coordinates small and wrap time or offsets modulo 256 (the noise's period) on the
// CPU. Requires GLSL 1.30+ (integer bit operations, texelFetch).

uniform sampler2D uPerlinPermutation;  // 256 x 1, R32F, texel i = P[i] in 0..255

const int PERLIN_TABLE_MASK = 255;        // the permutation's indices, 0..255
const float PERLIN_TABLE_SIZE = 256.0;    // the plain noise's period, a power of two

// One lookup in the permutation P of 0..255, in a texture the application binds
// (app/render/noise.py, GradientNoiseTextures: 256 x 1 R32F, texel i = P[i], read with texelFetch,
// no filtering). Seed None or 0 is Perlin's own table; other seeds are numpy
// default_rng(seed).permutation. A corner c's hash is Perlin's chained lookups,
//     h(c) = P[(P[(P[c.x mod 256] + c.y) mod 256] + c.z) mod 256]      (2D: two lookups).
// Any int is valid: the argument is wrapped into 0..255 first.
int PerlinPermutation(int i) {
    return int(texelFetch(uPerlinPermutation, ivec2(i & PERLIN_TABLE_MASK, 0), 0).r);
}

// The quintic fade s(t) = 6t^5 − 15t^4 + 10t^3 of t in [0, 1], in the reference's Horner order:
// s(0) = 0, s(1) = 1, s' = s'' = 0 at both ends, so value, gradient and second derivatives are
// continuous across cell faces (the 1985 cubic 3t^2 − 2t^3 left s'' discontinuous, creases in
// bump maps).
float PerlinFade(float t) { return t * t * t * (t * (t * 6.0 - 15.0) + 10.0); }
vec2 PerlinFade(vec2 t) { return t * t * t * (t * (t * 6.0 - 15.0) + 10.0); }
vec3 PerlinFade(vec3 t) { return t * t * t * (t * (t * 6.0 - 15.0) + 10.0); }

// a + t (b − a): the reference's interpolation, written out so the twin can match it.
float PerlinLerp(float t, float a, float b) { return a + t * (b - a); }

// g(h & 15) · d, the corner's linear ramp (0 at the corner, so the noise is 0 at every lattice
// point), d = p − c in cell units. The gradients are the 12 vectors from a cube's centre to its
// edge midpoints, (±1, ±1, 0), (±1, 0, ±1), (0, ±1, ±1), picked with Perlin's bit tests, without
// multiplications; entries 12..15 repeat (1, 1, 0), (−1, 1, 0), (0, −1, 1), (0, −1, −1), which
// avoids a division by 12 but gives y a slightly larger share: E[g_y²] = 3/4 against 5/8 for x
// and z, so an xy slice has a few per cent more energy along k_y than along k_x (measured in the
// tests, within 15%).
float PerlinGradient3(int hash, vec3 d) {
    int h = hash & 15;
    float u = h < 8 ? d.x : d.y;
    float v = h < 4 ? d.y : ((h == 12 || h == 14) ? d.x : d.z);
    return ((h & 1) == 0 ? u : -u) + ((h & 2) == 0 ? v : -v);
}

// The 2D gradient set, indexed by h & 7 (app.sim.noise.gradient.GRADIENTS2). Perlin gives none;
// ours: the 8 directions at 45° steps with length √2, g_k = √2 (cos 45k, sin 45k), symmetric
// under quarter turns.
const float PERLIN_SQRT2 = 1.41421356237310;
const vec2 kPerlinGradients2[8] = vec2[8](
    vec2(PERLIN_SQRT2, 0.0), vec2(1.0, 1.0), vec2(0.0, PERLIN_SQRT2), vec2(-1.0, 1.0),
    vec2(-PERLIN_SQRT2, 0.0), vec2(-1.0, -1.0), vec2(0.0, -PERLIN_SQRT2), vec2(1.0, -1.0));

// g(h & 7) · d, the 2D corner's linear ramp, d in cell units.
float PerlinGradient2(int hash, vec2 d) { return dot(kPerlinGradients2[hash & 7], d); }

// Euclidean remainder of integral floats by positive ints: floor(p) mod period in
// [0, period). Failure cases: the mod is taken in float, so a huge p cannot overflow an int.
// mod() of an integral float by a period that is not a power of two rounds: near multiples of
// the period it may give −1 or period, and beyond |p| ~ 2^24 (where every float is an integer)
// it is off by up to one ulp. So mod is taken twice (the second on a small integer, exact) and
// the edges are fixed with integer compares and a clamp: the index is always in [0, period).
// Below 2^24 it is exact and equals the twin's; above, the noise stays finite and bounded but
// no longer matches the twin (nor means anything: f = 0).
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
// corners and the offset f in [0, 1)^3, shared by the plain and the periodic noise: the 8
// corners' ramps blended with PerlinFade(f).
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

// Improved noise at p (lattice units), period 256 on every axis. Range: the fade weights are
// non-negative, so |noise| ≤ max over the cell of Σ_c w_c(f) max_g g · (p − c), 1.0363538 for
// this set (at f ~ (0.355, 0.481, 0.5) and its mirror images); a given permutation stays below.
// Failure cases: negative p, whose cell is floor(p) (int() would truncate toward zero), so
// f = p − floor(p) stays in [0, 1); a huge p, wrapped into [0, 256) in float before any int
// conversion (exact for every float: 256 is a power of two).
float PerlinNoise3(vec3 p) {
    vec3 cell = floor(p);
    ivec3 i0 = ivec3(mod(cell, PERLIN_TABLE_SIZE)) & PERLIN_TABLE_MASK;
    return PerlinNoise3Lattice(i0, (i0 + 1) & PERLIN_TABLE_MASK, p - cell);
}

// The same noise with the lattice wrapped modulo `period` (in lattice units): it tiles with
// that period. PerlinNoise3Periodic(p, ivec3(256)) == PerlinNoise3(p). Failure case: a period
// below 1 (no meaningful tiling) is the caller's error; it is clamped to 1 (noise 0).
float PerlinNoise3Periodic(vec3 p, ivec3 period) {
    period = max(period, ivec3(1));
    vec3 cell = floor(p);
    ivec3 i0 = PerlinWrapIndex(cell, period);
    ivec3 i1 = i0 + 1;
    i1 -= period * ivec3(greaterThanEqual(i1, period));
    return PerlinNoise3Lattice(i0, i1, p - cell);
}

// ---- 2D ------------------------------------------------------------------------------------

// The 2D twin of PerlinNoise3Lattice: the 4 corners' ramps blended with PerlinFade(f).
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

// 2D gradient noise at p (the 8 gradients of kPerlinGradients2), period 256. |value| ≤ 1,
// exactly 1 at best (a cell's centre, all four gradients pointing at it). The failure cases are
// PerlinNoise3's.
float PerlinNoise2(vec2 p) {
    vec2 cell = floor(p);
    ivec2 i0 = ivec2(mod(cell, PERLIN_TABLE_SIZE)) & PERLIN_TABLE_MASK;
    return PerlinNoise2Lattice(i0, (i0 + 1) & PERLIN_TABLE_MASK, p - cell);
}

// The 2D noise wrapped modulo `period`, as PerlinNoise3Periodic.
float PerlinNoise2Periodic(vec2 p, ivec2 period) {
    period = max(period, ivec2(1));
    vec2 cell = floor(p);
    ivec2 i0 = PerlinWrapIndex(cell, period);
    ivec2 i1 = i0 + 1;
    i1 -= period * ivec2(greaterThanEqual(i1, period));
    return PerlinNoise2Lattice(i0, i1, p - cell);
}
