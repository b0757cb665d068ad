// =============================================================================================
// The procedural-wood thesis's lattice value noise, exactly as documented
// (spec/004 §1.5–1.6; thesis §4.2 and §5.5–5.7).
//
//   hash  getPixel(i):  f = (i / 256) mod 1
//                       pix = T(f.xy);  pix = T((pix.rg + f.yz) mod 1);
//                       pix = T((pix.rg + f.zx) mod 1)
//         T = the seedable 256×256 RGB random texture, read with texelFetch at floor(u·256)
//         (bilinear filtering would blend neighbouring texels and lower the variance)
//   noise3(p):  p wrapped by divmod3 into [0, Texture2DImageSize); the 8 corner values of the
//         unit cell are interpolated z, then y, then x, each weight through the cubic fade
//         c(t) = 3t² − 2t³ (easeInOut): value noise, C¹, in [0, 1]³ — not gradient noise.
//   octaves(p, d) = Σ_{i<d} 2^-i noise3(2^i p) / Σ_{i<d} 2^-i,  d = RecDepth clamped to [1, 8]
//
// Failure cases guarded: negative coordinates (floor-based wrap, no seam at 0); indices that
// reach 256 (wrapped by the mod); depth outside 1…8 (clamped).
// Twin: app/sim/noise/value.py.
// =============================================================================================

uniform sampler2D uValueNoiseTex;  // 256×256 RGBA8, texelFetch only
uniform vec3 uValueNoiseWrap;      // Texture2DImageSize.xyz·w, the wrap of noise3's input (256)

// easeInOut: 0 at x ≤ 0, 1 at x ≥ 1, (3 − 2x)x² between.
float ThesisEaseInOut(float x) {
    if (x <= 0.0) return 0.0;
    if (x >= 1.0) return 1.0;
    return (3.0 - 2.0 * x) * x * x;
}

// getPixel(i): the header's three chained lookups of the random texture T for the lattice
// point i (integer coordinates; any value, wrapped by mod 256), an RGB value in [0, 1]³.
vec3 ThesisGetPixel(vec3 indices) {
    vec3 f = mod(indices / 256.0, 1.0);
    vec4 pix = texelFetch(uValueNoiseTex, ivec2(f.xy * 256.0), 0);
    pix = texelFetch(uValueNoiseTex, ivec2(mod(pix.rg + f.yz, 1.0) * 256.0), 0);
    pix = texelFetch(uValueNoiseTex, ivec2(mod(pix.rg + f.zx, 1.0) * 256.0), 0);
    return pix.rgb;
}

// noise3(p): the thesis's value noise at p (lattice units), in [0, 1]³. p is wrapped into
// [0, uValueNoiseWrap) by the floor-based remainder, so negative coordinates have no seam;
// the cell's 8 corner values are blended z, then y, then x with the cubic fade.
vec3 ThesisNoise3(vec3 p) {
    vec3 wrap = uValueNoiseWrap;
    vec3 q = p - floor(p / wrap) * wrap;  // divmod3 remainder, non-negative
    vec3 i = floor(q);
    vec3 t = q - i;
    vec3 c000 = ThesisGetPixel(i + vec3(0, 0, 0));
    vec3 c001 = ThesisGetPixel(i + vec3(0, 0, 1));
    vec3 c010 = ThesisGetPixel(i + vec3(0, 1, 0));
    vec3 c011 = ThesisGetPixel(i + vec3(0, 1, 1));
    vec3 c100 = ThesisGetPixel(i + vec3(1, 0, 0));
    vec3 c101 = ThesisGetPixel(i + vec3(1, 0, 1));
    vec3 c110 = ThesisGetPixel(i + vec3(1, 1, 0));
    vec3 c111 = ThesisGetPixel(i + vec3(1, 1, 1));
    float wz = ThesisEaseInOut(t.z), wy = ThesisEaseInOut(t.y), wx = ThesisEaseInOut(t.x);
    // z first, then y, then x, as the thesis's code does
    vec3 c00 = mix(c000, c001, wz), c01 = mix(c010, c011, wz);
    vec3 c10 = mix(c100, c101, wz), c11 = mix(c110, c111, wz);
    vec3 c0 = mix(c00, c01, wy), c1 = mix(c10, c11, wy);
    return mix(c0, c1, wx);
}

// octaves(p, d): the normalised sum of d octaves of noise3, octave i at 2^i p with weight
// 2^-i, in [0, 1]³. A depth outside 1…8 (RecDepth) is clamped.
vec3 ThesisOctaves(vec3 p, int depth) {
    int d = clamp(depth, 1, 8);
    vec3 sum = vec3(0.0);
    float total = 0.0, weight = 1.0, scale = 1.0;
    for (int i = 0; i < 8; ++i) {
        if (i >= d) break;
        sum += ThesisNoise3(p * scale) * weight;
        total += weight;
        weight *= 0.5;
        scale *= 2.0;
    }
    return sum / total;
}
