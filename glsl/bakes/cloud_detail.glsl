// Cloud detail noise: the small 3D texture that erodes the cloud edges — three inverted-Worley
// fBm channels of rising frequency in R, G, B, and A = 1 exactly.
//
// Sources
// -------
// * spec/001 texture table, "Detail": 3D, 32³, RGB, "three Worley noises of increasing
//   frequency (d_r, d_g, d_b)", used by spec/001 eq. 4.14 DetalleBase = 0.625 d_r + 0.25 d_g
//   + 0.125 d_b; criteria B1-B5.
// * spec/000 §1.6 (NoiseSimulator): "Detail noise" RGB 64³, multi-frequency Worley per channel,
//   tileable (27 wrapped neighbour cells); "writing to the detail texture's unused channel A
//   runs a kernel that fills the whole channel with ones" — criterion 15: A is exactly 1.0.
//   Criterion 14: tiles, channels with higher frequency show more zero crossings and gradient
//   energy.
// Cell counts and octaves are not in either thesis: ours are the bake_detail defaults
// (app/bakes/params.py).
//
// Equations (uvw in [0, 1)³ the texel centre; one tile = one unit of uvw):
//
//   d_c = WorleyFbm(C_c uvw) = Σ_{i<n} G^i (1 - clamp(F1(2^i C_c uvw), 0, 1)) / Σ_{i<n} G^i
//         with octave i wrapped with period C_c·2^i (tiles with period 1 in uvw)
//                                                                    (spec/001 eq. 3.2)
//   C_r < C_g < C_b;  A = 1.0 (written as the literal 1.0: exact in every format)
//
// After the bake (app/bakes/core.py): R, G, B are stretched to [0, 1] by their min and max
// (bake_detail.normalize, spec/001 B1); A stays 1.0 -> 255 in RGBA8, which samples as 1.0.
//
// Seeds: uint seed uDetailSeed·8 + 4 + channel (R 4, G 5, B 6) — independent channels, and
// independent of the shape texture's channels (which use seed·8 + 0..3).
//
// Failure cases
// -------------
// * Small textures alias the top octaves: at 32³ with C_b = 8 and 3 octaves the last octave
//   has 32 cells, one per texel — it reads as fine grain, and the frequency order of the
//   channels still holds (tested). Fewer octaves or a larger size avoid it.
// * Octave counts outside 1..16 are clamped (FbmOctaves); cells < 1 are clamped to 1.
// Numpy twin: app/sim/bakes.py (detail_reference).

#include "noise_fbm.glsl"

uniform uint uDetailSeed;
uniform ivec3 uDetailCells;       // R, G, B: Worley cells per tile of octave 0
uniform int uDetailOctaves;       // octaves of each Worley fBm
uniform float uDetailGain;        // octave gain G (persistence)

float DetailWorleyChannel(vec3 uvw, int cells, uint channel) {
    return WorleyFbm3Periodic(uvw * float(cells), ivec3(cells), uDetailOctaves, 2, uDetailGain,
                              uDetailSeed * 8u + 4u + channel);
}

vec4 BakeValue(vec3 uvw) {
    return vec4(DetailWorleyChannel(uvw, uDetailCells.x, 0u),
                DetailWorleyChannel(uvw, uDetailCells.y, 1u),
                DetailWorleyChannel(uvw, uDetailCells.z, 2u),
                1.0);
}
