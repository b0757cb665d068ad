// Amortised marching of an expensive full-screen layer, the march's side (beyond the theses;
// after Schneider 2015, the clouds of Horizon: Zero Dawn). Python: app/render/amortise.py;
// numpy twins: app/sim/amortise.py; the resolve: amortise_resolve.frag.
//
// A march pass draws into a grid of ceil(W/B) × ceil(H/B) texels, B = uAmortiseBlock: texel t
// marches the full-resolution pixel t·B + uAmortiseSub (B = 1, sub (0, 0): every pixel of the
// frame, the un-amortised march). A ray's first sample is offset along it by
// AmortiseJitter: a 64² void-and-cluster blue-noise value plus the golden-ratio phase of the
// refresh cycle. Besides its layer (location 0) a march writes, at location 1,
// AmortiseAux(cloud distance, scene distance): the transmittance-weighted mean distance of what
// it met (AMORTISE_FAR when nothing) and the opaque scene's distance along the ray — what the
// resolve reprojects with and compares depths by.
// Failure cases guarded: a texel of the last row or column whose pixel lies off the image
// (W or H not a multiple of B) marches a valid ray all the same and the resolve ignores it; the
// blue-noise lookup wraps with a bit mask (its sides are powers of two; pixels are ≥ 0). B is a
// power of two, so blocks are shifts and masks (integer division is scalar on a software
// renderer).

uniform int uAmortiseBlock;        // full-resolution pixels per side between two marched rays
uniform int uAmortiseShift;        // log2 of it (the block is a power of two)
uniform ivec2 uAmortiseSub;        // the pixel of each block marched this pass
uniform vec2 uAmortiseFullSize;    // the full-resolution size (pixels)
uniform sampler2D uBlueNoise;      // R: blue-noise ranks in (0, 1), app.sim.amortise.blue_noise
uniform float uJitterPhase;        // frac(refresh cycle · φ)

uniform int uAmortiseBands;        // > 1: the grid is drawn banded (below); else as it is
uniform int uAmortiseBandRows;     // rows of each band
uniform int uAmortiseGridRows;     // the grid's rows
uniform int uAmortiseGridColumns;  // the grid's columns
uniform int uAmortiseBandShift;    // log2 of the fragment rows from one band to the next (≥ 6)

const float AMORTISE_FAR = 1.0e7;  // the cloud distance of a ray that met nothing (metres)

// A small grid fits one 64 × 64 tile, and a tiled software rasteriser (llvmpipe) shades a tile
// on one thread: there the grid is drawn in uAmortiseBands bands (app.render.amortise.bands),
// whole tiles each, so that each thread marches one. Band k holds the grid rows k, k + K,
// k + 2K … (K bands): interleaved, every band has its share of sky and of sea. Inside a band,
// each grid row is laid out in 4 × 4 blocks of 16 consecutive texels (its 4 fragment rows):
// llvmpipe runs a 4 × 4 block's fragments as lanes of one vector, and a loop runs until its
// slowest lane is done, so the lanes hold rays of one elevation, whose marches are about as
// long, instead of rays from 2K grid rows apart. The same rays are marched either way;
// amortise_gather.frag puts them back in grid order.
const int AMORTISE_LANE_SHIFT = 2;  // a 4 × 4 block of fragments: one vector of lanes
const int AMORTISE_LANE = 1 << AMORTISE_LANE_SHIFT;
const int AMORTISE_LANE_MASK = AMORTISE_LANE - 1;
// (band, row of the band, column of the grid) of this fragment of a banded grid.
ivec3 AmortiseBandedTexel() {
    ivec2 f = ivec2(gl_FragCoord.xy);
    int y = f.y & ((1 << uAmortiseBandShift) - 1);
    int x = ((f.x >> AMORTISE_LANE_SHIFT) << (2 * AMORTISE_LANE_SHIFT))
          + ((y & AMORTISE_LANE_MASK) << AMORTISE_LANE_SHIFT) + (f.x & AMORTISE_LANE_MASK);
    return ivec3(f.y >> uAmortiseBandShift, y >> AMORTISE_LANE_SHIFT, x);
}
// Whether this fragment is a banded grid's padding (it marches nothing: discard it).
bool AmortisePadding() {
    if (uAmortiseBands <= 1) return false;
    ivec3 b = AmortiseBandedTexel();
    return b.y >= uAmortiseBandRows || b.y * uAmortiseBands + b.x >= uAmortiseGridRows
        || b.z >= uAmortiseGridColumns;
}
// The grid texel this fragment marches.
ivec2 AmortiseGridTexel() {
    if (uAmortiseBands > 1) {
        ivec3 b = AmortiseBandedTexel();
        return ivec2(b.z, b.y * uAmortiseBands + b.x);
    }
    return ivec2(gl_FragCoord.xy);
}
// The full-resolution pixel this fragment marches.
ivec2 AmortisedPixel() {
    return (AmortiseGridTexel() << uAmortiseShift) + uAmortiseSub;
}

// Its uv in [0, 1]² (pixel centre, (0, 0) at the bottom left).
vec2 AmortisedUV(ivec2 pixel) {
    return (vec2(pixel) + 0.5) / uAmortiseFullSize;
}

// Blue-noise jitter in [0, 1) of the first sample, this refresh cycle.
float AmortiseJitter(ivec2 pixel) {
    ivec2 n = textureSize(uBlueNoise, 0);  // a power of two per side
    float v = texelFetch(uBlueNoise, pixel & (n - 1), 0).r;
    return fract(v + uJitterPhase);
}

// The aux output of a march: (cloud distance, scene distance, 0, 0).
vec4 AmortiseAux(float cloudDistance, float sceneDistance) {
    return vec4(cloudDistance, sceneDistance, 0.0, 0.0);
}

// Whether two opaque-scene distances of neighbouring rays (clipped at the layer's far
// distance) are one surface: |a − b| ≤ 5 % of the larger + 1 m (app.sim.amortise.depth_agree).
bool AmortiseDepthAgree(float a, float b) {
    return abs(a - b) <= 0.05 * max(a, b) + 1.0;
}
