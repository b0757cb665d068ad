// Worley (cellular) noise, 2D and 3D, plain and periodic: F1, F2, F2 − F1, inverted F1
// (Worley 1996, "A cellular texture basis function"): the cloud thesis's shape and detail
// channels (spec/001 §1.1, Worley [50], table "Shape"/"Detail", criteria B2–B4) and the maritime
// thesis's NoiseSimulator (spec/000 §1.6: tileable, 9 / 27 neighbour cells, "the same point
// distribution shifted"). Numpy twin: app/sim/noise/cellular.py (worley3, worley2,
// worley3_periodic, worley2_periodic, ...). Every cell of the unit lattice holds exactly one
// feature point (Worley draws a Poisson number; the theses use one); distances in cell units.
// Failure cases guarded, each at its function: negative cells, the periodic wrap of huge or
// negative coordinates (GLSL's % is undefined for negative operands), a period below 1, and
// F1 > 1. Beyond |p| ~ 2^16 float32 loses p's fraction: wrap coordinates or use the periodic
// variant. Requires GLSL 1.30+ (uint arithmetic).

const uint PCG_MULTIPLIER = 1664525u;      // the LCG step of PCG4D
const uint PCG_INCREMENT = 1013904223u;
const uint PCG_XOR_SHIFT = 16u;            // bits folded down between the rounds
const uint WORLEY_OFFSET_SHIFT = 8u;       // keep a hash's top 24 bits
const float WORLEY_OFFSET_SCALE = 1.0 / 16777216.0;  // 2^-24: 24 bits onto [0, 1), exact
const float WORLEY_NO_POINT = 1e30;        // squared distance before any point is seen

// PCG4D (Jarzynski & Olano 2020, "Hash Functions for GPU Rendering", JCGT): four 32-bit hashes
// from four 32-bit inputs, (c.x, c.y, c.z, seed), in uint arithmetic, which wraps mod 2^32, so
// the numpy twin reproduces it bit for bit: v = v · 1664525 + 1013904223, then two rounds of
//     v.x += v.y v.w;  v.y += v.z v.x;  v.z += v.x v.y;  v.w += v.y v.z
// with v ^= v >> 16 between them. Any input is valid.
uvec4 Pcg4d(uvec4 v) {
    v = v * PCG_MULTIPLIER + PCG_INCREMENT;
    v.x += v.y * v.w; v.y += v.z * v.x; v.z += v.x * v.y; v.w += v.y * v.z;
    v ^= v >> PCG_XOR_SHIFT;
    v.x += v.y * v.w; v.y += v.z * v.x; v.z += v.x * v.y; v.w += v.y * v.z;
    return v;
}

// o(c) in [0, 1)^n: the feature point's position inside the cell c, the hash's top 24 bits,
// o = float(h >> 8) / 2^24, exact in float32. The feature point is x_c = c + o(c). Failure
// case: a negative cell; uint(int) keeps its two's-complement bits (GLSL spec), as the twin.
// The 2D offset hashes (c.x, c.y, 0, seed).
vec3 WorleyFeatureOffset3(ivec3 cell, uint seed) {
    uvec4 h = Pcg4d(uvec4(uvec3(cell), seed));
    return vec3(h.xyz >> WORLEY_OFFSET_SHIFT) * WORLEY_OFFSET_SCALE;
}

vec2 WorleyFeatureOffset2(ivec2 cell, uint seed) {
    uvec4 h = Pcg4d(uvec4(uvec2(cell), 0u, seed));
    return vec2(h.xy >> WORLEY_OFFSET_SHIFT) * WORLEY_OFFSET_SCALE;
}

// The periodic variant's cell, floor(p) mod period, in [0, period). Failure cases: the modulo is
// taken in float (no int overflow for a huge p), twice (the second time on a small integer,
// exact), then fixed up into [0, period) with integer compares and a clamp (as PerlinWrapIndex
// in noise_perlin.glsl: exact below |p| ~ 2^24, bounded beyond); the search then wraps the
// neighbours from there with non-negative ints only.
ivec3 WorleyWrapCell(vec3 cellFloor, ivec3 period) {
    vec3 r = mod(mod(cellFloor, vec3(period)), vec3(period));
    ivec3 i = ivec3(r);
    i += period * ivec3(lessThan(i, ivec3(0)));
    i -= period * ivec3(greaterThanEqual(i, period));
    return clamp(i, ivec3(0), period - 1);
}

ivec2 WorleyWrapCell(vec2 cellFloor, ivec2 period) {
    vec2 r = mod(mod(cellFloor, vec2(period)), vec2(period));
    ivec2 i = ivec2(r);
    i += period * ivec2(lessThan(i, ivec2(0)));
    i -= period * ivec2(greaterThanEqual(i, period));
    return clamp(i, ivec2(0), period - 1);
}

// Keep the two smallest squared distances, (F1², F2²), with one more, in squared cell units.
vec2 WorleyInsertDistance(vec2 nearest, float distanceSquared) {
    return vec2(min(nearest.x, distanceSquared),
                min(nearest.y, max(nearest.x, distanceSquared)));
}

// ---- 3D ------------------------------------------------------------------------------------

// (F1, F2) at p in cell units: F1(p) = min_c |p − x_c|, F2 the second smallest |p − x_c|, over
// the 3^n cells around p's own (27 in 3D, 9 in 2D). A point two cells away is at least 1 away
// along that axis, so F1 (F2) is exact wherever it is < 1; where larger (rare clusters of far-off
// points) it is the distance to the nearest (second nearest) visited point, the same on CPU and
// GPU. Distances are taken from p's offset in its cell, f = p − floor(p), as
// d = n + o(c + n) − f for the neighbour offset n ∈ {−1, 0, 1}^n, so float32 precision does not
// depend on where the cell is. With `periodic` the cell index c + n wraps modulo `period` before
// it is hashed while d keeps the unwrapped n: across the wrap the search sees the other side's
// points shifted by one period, and the pattern tiles. Failure cases: a period below 1 is
// clamped to 1; the plain noise converts floor(p) to int, so |p| must stay below 2^31 (beyond,
// the cell is undefined but the result is still a finite distance).
vec2 WorleyNoise3Search(vec3 p, bool periodic, ivec3 period, uint seed) {
    vec3 cellFloor = floor(p);
    vec3 f = p - cellFloor;
    period = max(period, ivec3(1));
    ivec3 cell = periodic ? WorleyWrapCell(cellFloor, period) : ivec3(cellFloor);
    vec2 nearest = vec2(WORLEY_NO_POINT);
    for (int z = -1; z <= 1; ++z)
    for (int y = -1; y <= 1; ++y)
    for (int x = -1; x <= 1; ++x) {
        ivec3 n = ivec3(x, y, z);
        ivec3 c = periodic ? (cell + n + period) % period : cell + n;
        vec3 d = vec3(n) + WorleyFeatureOffset3(c, seed) - f;
        nearest = WorleyInsertDistance(nearest, dot(d, d));
    }
    return sqrt(nearest);
}

vec2 WorleyNoise3(vec3 p, uint seed) { return WorleyNoise3Search(p, false, ivec3(1), seed); }

vec2 WorleyNoise3Periodic(vec3 p, ivec3 period, uint seed) {
    return WorleyNoise3Search(p, true, period, seed);
}

// ---- 2D ------------------------------------------------------------------------------------

// The 2D twin of WorleyNoise3Search (the same model and failure cases).
vec2 WorleyNoise2Search(vec2 p, bool periodic, ivec2 period, uint seed) {
    vec2 cellFloor = floor(p);
    vec2 f = p - cellFloor;
    period = max(period, ivec2(1));
    ivec2 cell = periodic ? WorleyWrapCell(cellFloor, period) : ivec2(cellFloor);
    vec2 nearest = vec2(WORLEY_NO_POINT);
    for (int y = -1; y <= 1; ++y)
    for (int x = -1; x <= 1; ++x) {
        ivec2 n = ivec2(x, y);
        ivec2 c = periodic ? (cell + n + period) % period : cell + n;
        vec2 d = vec2(n) + WorleyFeatureOffset2(c, seed) - f;
        nearest = WorleyInsertDistance(nearest, dot(d, d));
    }
    return sqrt(nearest);
}

vec2 WorleyNoise2(vec2 p, uint seed) { return WorleyNoise2Search(p, false, ivec2(1), seed); }

vec2 WorleyNoise2Periodic(vec2 p, ivec2 period, uint seed) {
    return WorleyNoise2Search(p, true, period, seed);
}

// ---- derived values ------------------------------------------------------------------------

// F2 − F1 from (F1, F2): 0 on the borders between cells (Voronoi edges), rising toward the
// cells' cores; cell units.
float WorleyF2MinusF1(vec2 f1f2) { return f1f2.y - f1f2.x; }

// 1 − clamp(F1, 0, 1): exactly 1 at feature points (spec/001 §1.1, criterion B4), 0 at
// distance ≥ 1: the clouds' billows. Failure case: F1 > 1 (see WorleyNoise3Search) clamps to 0.
float WorleyInvertedF1(vec2 f1f2) { return 1.0 - clamp(f1f2.x, 0.0, 1.0); }
