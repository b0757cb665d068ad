// Worley (cellular) noise, 2D and 3D, plain and periodic: F1, F2, F2 - F1, inverted F1.
//
// Source: S. Worley, "A cellular texture basis function", SIGGRAPH 1996 — the cloud thesis's
// shape and detail channels (spec/001 §1.1, Worley [50], table "Shape"/"Detail", criteria
// B2-B4) and the maritime thesis's NoiseSimulator (spec/000 §1.6: tileable, 9 / 27
// neighbour cells, "the same point distribution shifted"). Numpy twin: app/sim/noise/cellular.py
// (worley3, worley2, worley3_periodic, worley2_periodic, ...).
//
// The model
// ---------
// Every cell c of the unit lattice holds one feature point x_c = c + o(c), o(c) in [0, 1)^n
// (Worley draws a Poisson number of points per cell; the theses use exactly one). Then
//
//     F1(p) = min_c |p - x_c|,     F2(p) = the second smallest |p - x_c|     (cell units)
//
// searched over the 3^n cells around p's own (9 in 2D, 27 in 3D). A point two cells away is
// at least 1 away along that axis, so F1 (F2) is exact wherever it is < 1; where it is larger
// (rare clusters of far-off points) it is the distance to the nearest (second nearest)
// visited point — the same on CPU and GPU. Distances are computed from p's offset inside its
// cell, f = p - floor(p), as d = n + o(c + n) - f for the neighbour offset n in {-1,0,1}^n,
// which keeps float32 precision independent of where the cell is.
//
// Derived values:  F2 - F1 (0 on Voronoi borders)  and the inverted F1,
//                  1 - clamp(F1, 0, 1), which is exactly 1 at feature points (spec/001 B4).
//
// Periodic variant: the cell index c + n is wrapped modulo an integer period before it is
// hashed; the distance still uses the unwrapped n, so the search across the wrap sees the
// feature points of the opposite side shifted by one period and the pattern tiles.
//
// Hash: PCG4D (Jarzynski & Olano, "Hash Functions for GPU Rendering", JCGT 2020) of
// (c.x, c.y, c.z, seed) in uint arithmetic (wraps mod 2^32 — reproduced bit for bit by the
// numpy twin): v = v * 1664525 + 1013904223; two rounds of
//     v.x += v.y v.w;  v.y += v.z v.x;  v.z += v.x v.y;  v.w += v.y v.z
// with v ^= v >> 16 between them. 2D hashes (c.x, c.y, 0, seed). The offset is the top 24
// bits, o = float(h >> 8) / 2^24, exact in float32.
//
// Failure cases guarded
// ---------------------
// * Negative cells: uint(int) keeps the two's-complement bit pattern (GLSL spec), as the twin.
// * Periodic wrap: floor(p) mod period is taken in float (no int overflow for huge p), twice
//   (the second time on a small integer, exact), then fixed up into [0, period) with integer
//   compares and a clamp (as PerlinWrapIndex in noise_perlin.glsl: exact below |p| ~ 2^24,
//   bounded beyond); neighbours are wrapped from there with non-negative ints only (GLSL's %
//   is undefined for negative operands).
// * The plain noise converts floor(p) to int: |p| must stay below 2^31 (beyond, the cell is
//   undefined but the result is still a finite distance).
// * Precision: beyond |p| ~ 2^16 float32 loses the fraction of p — wrap coordinates or use
//   the periodic variant. period < 1 is clamped to 1.
// * F1 > 1 (see above) is clamped by the inverted F1, which then reads 0.
//
// Requires GLSL 1.30+ (uint arithmetic).

// PCG4D: four 32-bit hashes from four 32-bit inputs.
uvec4 Pcg4d(uvec4 v) {
    v = v * 1664525u + 1013904223u;
    v.x += v.y * v.w; v.y += v.z * v.x; v.z += v.x * v.y; v.w += v.y * v.z;
    v ^= v >> 16u;
    v.x += v.y * v.w; v.y += v.z * v.x; v.z += v.x * v.y; v.w += v.y * v.z;
    return v;
}

// o(c) in [0, 1)^n: the feature point's position inside cell c.
vec3 WorleyFeatureOffset3(ivec3 cell, uint seed) {
    uvec4 h = Pcg4d(uvec4(uvec3(cell), seed));
    return vec3(h.xyz >> 8u) * (1.0 / 16777216.0);
}

vec2 WorleyFeatureOffset2(ivec2 cell, uint seed) {
    uvec4 h = Pcg4d(uvec4(uvec2(cell), 0u, seed));
    return vec2(h.xy >> 8u) * (1.0 / 16777216.0);
}

// floor(p) mod period in [0, period) (see the failure cases).
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

// Keep the two smallest squared distances: (F1^2, F2^2).
vec2 WorleyInsertDistance(vec2 nearest, float distanceSquared) {
    return vec2(min(nearest.x, distanceSquared), min(nearest.y, max(nearest.x, distanceSquared)));
}

// ---- 3D ------------------------------------------------------------------------------------

// (F1, F2) at p. With `periodic`, cell indices wrap modulo `period` (tiles with it).
vec2 WorleyNoise3Search(vec3 p, bool periodic, ivec3 period, uint seed) {
    vec3 cellFloor = floor(p);
    vec3 f = p - cellFloor;
    period = max(period, ivec3(1));
    ivec3 cell = periodic ? WorleyWrapCell(cellFloor, period) : ivec3(cellFloor);
    vec2 nearest = vec2(1e30);
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

vec2 WorleyNoise2Search(vec2 p, bool periodic, ivec2 period, uint seed) {
    vec2 cellFloor = floor(p);
    vec2 f = p - cellFloor;
    period = max(period, ivec2(1));
    ivec2 cell = periodic ? WorleyWrapCell(cellFloor, period) : ivec2(cellFloor);
    vec2 nearest = vec2(1e30);
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

// F2 - F1 from (F1, F2): 0 on the borders between cells, rising toward the cells' cores.
float WorleyF2MinusF1(vec2 f1f2) { return f1f2.y - f1f2.x; }

// 1 - clamp(F1, 0, 1): 1 at feature points, 0 at distance >= 1 — the clouds' billows.
float WorleyInvertedF1(vec2 f1f2) { return 1.0 - clamp(f1f2.x, 0.0, 1.0); }
