#version 330 core
// =============================================================================================
// Amortised layer, the gather (beyond the theses; a speed path for tiled software
// rasterisers, app/render/amortise.py). A small march grid is drawn in uAmortiseBands bands
// of whole 64-row tiles, so that each tile, a thread of llvmpipe, marches one; band k holds the
// grid rows k, k + K, k + 2K …, each laid out in 4 × 4 blocks of 16 consecutive texels
// (amortise.glsl) — and this pass copies them back into the compact grid the resolve reads.
// No equation: texel (x, y) of the grid is texel (4·⌊x / 16⌋ + x mod 4,
// 2^S·(y mod K) + 4·⌊y / K⌋ + ⌊x / 4⌋ mod 4) of the banded target, 2^S its band's rows.
// Failure cases guarded: none beyond the copy; the grid's size bounds every fetch.
// =============================================================================================

in vec2 vUV;
layout(location = 0) out vec4 outLayer;
layout(location = 1) out vec2 outAux;

uniform sampler2D uBanded;     // the banded march: layer
uniform sampler2D uBandedAux;  // its aux (cloud distance, scene distance)
uniform int uAmortiseBands;      // K, the bands (> 1)
uniform int uAmortiseBandShift;  // S: log2 of the fragment rows from one band to the next

void main() {
    ivec2 g = ivec2(gl_FragCoord.xy);
    int band = g.y % uAmortiseBands;
    int row = g.y / uAmortiseBands;
    ivec2 s = ivec2(((g.x >> 4) << 2) + (g.x & 3),
                    (band << uAmortiseBandShift) + (row << 2) + ((g.x >> 2) & 3));
    outLayer = texelFetch(uBanded, s, 0);
    outAux = texelFetch(uBandedAux, s, 0).xy;
}
