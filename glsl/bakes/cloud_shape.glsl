// Cloud shape noise: the 3D RGBA texture the cloud density erodes (Perlin-Worley base in R,
// three inverted-Worley fBm channels of rising cell count in G, B, A). Baked once, cached on
// disk (app/bakes), sampled with trilinear filtering and repeat wrapping by the cloud shader.
//
// Sources
// -------
// * spec/001 §1.1 (Ch. 3.2, 5.1.1) and its texture table, "Shape": 3D, 128³, RGBA;
//   R = Perlin-Worley (f_r), G, B, A = Worley with increasing cell counts (f_g, f_b, f_a),
//   "starting with a few in the red channel"; Worley inverted for billows (Fig. 3.20); the
//   noise must be periodic (stock FastNoise was dropped for not tiling, §1.1 and §4). The
//   thesis gives no cell counts, octave counts, blend formula or seeds: ours are the
//   bake_shape defaults in app/bakes/params.py (R: 3 cells, G/B/A: 4, 8, 16 cells).
// * spec/000 §1.6 (NoiseSimulator): "Volume noise" RGBA 132³, multi-frequency Worley per
//   channel, tileable with the 27-cell wrapped search; criteria 14 (tiles, rising
//   frequency) and spec/001 B1-B5.
// * Perlin-Worley after Schneider 2015 (spec/001 §1.1); the exact remap is
//   PerlinWorleyRemap in glsl/common/noise_fbm.glsl.
//
// Equations (uvw in [0, 1)³ is the texel centre, so the tile is one unit of uvw):
//
//   fBm (spec/001 eq. 3.2), normalised, lacunarity 2:
//                                         F(p) = Σ_{i<n} G^i noise(2^i p) / Σ_{i<n} G^i
//   R = PW = clamp((P + 1 - W) / (2 - W), 0, 1),  P = clamp(0.5 + 0.5 PerlinFbm(B uvw), 0, 1),
//                                                 W = WorleyFbm(B uvw)        (B = base period)
//   G = WorleyFbm(C_g uvw),  B = WorleyFbm(C_b uvw),  A = WorleyFbm(C_a uvw)   (C_g < C_b < C_a)
//   WorleyFbm = fBm of the inverted F1, 1 - clamp(F1, 0, 1)   (1 at feature points)
//
// Tiling: octave i of a sum with base period N uses the periodic noise with period N·2^i
// (lattice/cells wrapped before hashing), so every channel repeats with period 1 in uvw and
// the last texel is followed by the first exactly as any two interior neighbours are — for any
// texture size, 128 or 132 alike.
//
// After the bake (app/bakes/core.py, on the CPU): G, B, A are stretched to [0, 1] by their min
// and max over the volume (bake_shape.normalize; spec/001 B1 wants each Worley channel to span
// at least [0.05, 0.95], and a 3-octave fBm alone spans about [0.04, 0.94]); R keeps the
// Perlin-Worley values (about [0.41, 0.87]); then u8 = round(255 clamp(v, 0, 1)), RGBA8.
//
// Seeds: the Perlin fBm uses the permutation of uShapeSeed (bound to uPerlinPermutation by
// app/bakes; 0 is Perlin's own table); the Worley sums use uint seeds uShapeSeed·8 + channel
// (R 0, G 1, B 2, A 3), so the channels are independent of each other (with one seed for all,
// octave 1 of G would be octave 0 of B, bit for bit).
//
// Failure cases
// -------------
// * Top octaves above the Nyquist rate alias (C·2^(n-1) cells on fewer than ~2 texels per
//   cell): no crash, just white-ish noise in the high octaves; the defaults stay at ≥ 2 texels
//   per cell at 128³ (16·2² = 64 cells).
// * Octave counts outside 1..16 are clamped by FbmOctaves; periods < 1 are clamped to 1.
// * Perlin noise is 0 at its lattice points (noise_fbm.glsl). A texel centre (g + 0.5)/N
//   lies on octave i's lattice planes when B·2^i/N reduces to even/odd (at 132³, octave 3 of
//   R: 24/132 = 2/11, planes through texels 5, 16, 27, ...); where three such planes cross,
//   that one octave adds 0 — a few texels, invisible. At 128³ it never happens.
// Numpy twin: app/sim/bakes.py (shape_reference), which the bake tests compare with.

#include "noise_fbm.glsl"

uniform uint uShapeSeed;           // Worley seed base; the Perlin seed is the bound permutation
uniform int uShapeBasePeriod;      // R: Perlin lattice cells and Worley cells per tile
uniform int uShapePerlinOctaves;   // R: octaves of the Perlin fBm
uniform int uShapeBaseWorleyOctaves;  // R: octaves of the Worley fBm in Perlin-Worley
uniform ivec3 uShapeCells;         // G, B, A: Worley cells per tile of octave 0
uniform int uShapeWorleyOctaves;   // G, B, A: octaves of each Worley fBm
uniform float uShapeGain;          // octave gain G of every sum (persistence; 2^-H)

float ShapeWorleyChannel(vec3 uvw, int cells, uint channel) {
    return WorleyFbm3Periodic(uvw * float(cells), ivec3(cells), uShapeWorleyOctaves, 2, uShapeGain,
                              uShapeSeed * 8u + channel);
}

// The shape texture's texel at uvw ([0, 1)³, one tile per unit): R the Perlin-Worley remap PW
// of the base period B, G, B and A the three Worley fBm channels of uShapeCells (the header's
// equations), each in [0, 1] and periodic over the tile, so the bake tiles without a seam.
vec4 BakeValue(vec3 uvw) {
    vec3 p = uvw * float(uShapeBasePeriod);
    ivec3 period = ivec3(uShapeBasePeriod);
    float perlin = PerlinFbm3Periodic(p, period, uShapePerlinOctaves, 2, uShapeGain);
    float worley = WorleyFbm3Periodic(p, period, uShapeBaseWorleyOctaves, 2, uShapeGain,
                                      uShapeSeed * 8u);
    return vec4(PerlinWorleyRemap(perlin, worley),
                ShapeWorleyChannel(uvw, uShapeCells.x, 1u),
                ShapeWorleyChannel(uvw, uShapeCells.y, 2u),
                ShapeWorleyChannel(uvw, uShapeCells.z, 3u));
}
