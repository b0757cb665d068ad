#version 330 core
// =============================================================================================
// Amortised layer, the gather (beyond the theses; a speed path for tiled software
// rasterisers, app/render/amortise.py). A small march grid is drawn in uAmortiseBands bands,
// one 64-row tile each, so that each tile, a thread of llvmpipe, marches one; band k holds the
// grid rows k, k + K, k + 2K … — and this pass copies them back into the compact grid the
// resolve reads. No equation: texel (x, y) of the grid is texel (x, 64·(y mod K) + ⌊y / K⌋)
// of the banded target.
// Failure cases guarded: none beyond the copy; the grid's size bounds every fetch.
// =============================================================================================

in vec2 vUV;
layout(location = 0) out vec4 outLayer;
layout(location = 1) out vec2 outAux;

uniform sampler2D uBanded;     // the banded march: layer
uniform sampler2D uBandedAux;  // its aux (cloud distance, scene distance)
uniform int uAmortiseBands;    // K, the bands (> 1)

void main() {
    ivec2 g = ivec2(gl_FragCoord.xy);
    ivec2 s = ivec2(g.x, (g.y % uAmortiseBands) * 64 + g.y / uAmortiseBands);
    outLayer = texelFetch(uBanded, s, 0);
    outAux = texelFetch(uBandedAux, s, 0).xy;
}
