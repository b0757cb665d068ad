#version 330 core
// =============================================================================================
// The noise lab: one noise function or one baked texture on the screen, tiled 2×2 (or more) so a
// seam would show where the tiles meet — or four of them side by side in a 2×2 comparison.
// Live functions come from glsl/common/noise_*.glsl (Perlin 2002, Worley 1996, fBm, turbulence,
// Perlin–Worley, the wood thesis's value noise); bakes are the cloud shape / detail volumes and
// the weather map (glsl/bakes/, spec/001 §1.1, spec/000 §1.6), shown as a z slice of one channel
// or as RGB.
// Values are written so that a PNG (clamp tone map) shows them unchanged.
// Views: 0 shape, 1 detail, 2 weather, 3 Perlin, 4 Worley F1, 5 Worley F2 − F1, 6 Perlin fBm,
// 7 turbulence, 8 Perlin–Worley, 9 value noise (thesis).
// Layouts (uLayout): 0 one view; 1 kinds: Perlin fBm | Worley F1 over the shape bake's
// Perlin–Worley (R) | the thesis's value noise (spec/001 §1.1 fig. 5.1, spec/004 §1.5);
// 2 octaves: the view (a live one; a bake shows Perlin fBm) at 1, 2, 4 and 8 octaves
// (spec/001 eq. 3.2); 3 channels: the bake's R, G, B, A (the shape bake unless the view is the
// detail bake; spec/001 §1.1's texture table). Panels are parted by a dark line two pixels wide.
// Equations: the fBm views are the normalised spec/001 eq. 3.2 (noise_fbm.glsl); the value
// noise is spec/004 §1.5 (noise_value.glsl), made periodic here by wrapping its lattice indices.
// Failure cases: live functions use their periodic variants on fract(uv), so a seam between
// tiles means broken tiling, not a display artefact — but the period is int(uScale), so a
// fractional scale shows a seam by construction; octave counts are clamped by the noise
// library; values outside [0, 1] (Perlin beyond ±1) are clamped by the sRGB round trip.
// =============================================================================================
#include "noise_fbm.glsl"
#include "noise_value.glsl"
#include "tonemap.glsl"

in vec2 vUV;
out vec4 fragColor;

uniform int uView;
uniform int uLayout;       // 0 single, 1 kinds, 2 octaves, 3 channels
uniform int uChannel;      // 0 R, 1 G, 2 B, 3 A, 4 RGB
uniform float uSlice;      // z in [0, 1)
uniform float uTiles;      // how many repeats across the screen's height
uniform float uAspect;
uniform float uScale;      // lattice cells per tile for live functions
uniform int uOctaves;
uniform sampler3D uVolume;
uniform sampler2D uMap;

vec4 Pick(vec4 v, int channel) {
    if (channel == 4) return vec4(v.rgb, 1.0);
    float c = channel == 0 ? v.r : channel == 1 ? v.g : channel == 2 ? v.b : v.a;
    return vec4(vec3(c), 1.0);
}

// The thesis's value noise with its lattice indices wrapped at `period` (spec/004 §1.5): the
// same corner values as ThesisNoise3 inside one period, and seamless across tiles.
vec3 ThesisNoise3Periodic(vec3 p, vec3 period) {
    vec3 i = floor(p);
    vec3 t = p - i;
    vec3 i0 = mod(i, period), i1 = mod(i + 1.0, period);
    vec3 c000 = ThesisGetPixel(vec3(i0.x, i0.y, i0.z));
    vec3 c001 = ThesisGetPixel(vec3(i0.x, i0.y, i1.z));
    vec3 c010 = ThesisGetPixel(vec3(i0.x, i1.y, i0.z));
    vec3 c011 = ThesisGetPixel(vec3(i0.x, i1.y, i1.z));
    vec3 c100 = ThesisGetPixel(vec3(i1.x, i0.y, i0.z));
    vec3 c101 = ThesisGetPixel(vec3(i1.x, i0.y, i1.z));
    vec3 c110 = ThesisGetPixel(vec3(i1.x, i1.y, i0.z));
    vec3 c111 = ThesisGetPixel(vec3(i1.x, i1.y, i1.z));
    float wz = ThesisEaseInOut(t.z), wy = ThesisEaseInOut(t.y), wx = ThesisEaseInOut(t.x);
    vec3 c00 = mix(c000, c001, wz), c01 = mix(c010, c011, wz);
    vec3 c10 = mix(c100, c101, wz), c11 = mix(c110, c111, wz);
    return mix(mix(c00, c01, wy), mix(c10, c11, wy), wx);
}

// octaves(p, d) of spec/004 §1.5 over the periodic value noise: octave i has period 2^i·period.
vec3 ThesisOctavesPeriodic(vec3 p, vec3 period, int depth) {
    int d = clamp(depth, 1, 8);
    vec3 sum = vec3(0.0);
    float total = 0.0, weight = 1.0, scale = 1.0;
    for (int i = 0; i < 8; ++i) {
        if (i >= d) break;
        sum += ThesisNoise3Periodic(p * scale, period * scale) * weight;
        total += weight;
        weight *= 0.5;
        scale *= 2.0;
    }
    return sum / total;
}

// The grey value the noise lab shows at uv for a view: 0–1 a slice of the baked volume, 2 the
// 2-D map, 3–8 Perlin, Worley F1, F2 − F1, Perlin fBm, turbulence and Perlin-Worley computed
// live over uScale cells (periodic, so the tile repeats), else the thesis's value-noise
// octaves. Values in [0, 1] except where a noise's own range exceeds it.
vec4 Sample(int view, vec2 uv, int octaves) {
    if (view <= 1) return texture(uVolume, vec3(uv, uSlice));
    if (view == 2) return texture(uMap, uv);
    ivec3 period = ivec3(int(uScale));
    vec3 p = vec3(fract(uv), uSlice) * uScale;
    float n;
    if (view == 3) n = 0.5 + 0.5 * PerlinNoise3Periodic(p, period);
    else if (view == 4) n = WorleyNoise3Periodic(p, period, 0u).x;
    else if (view == 5) n = WorleyF2MinusF1(WorleyNoise3Periodic(p, period, 0u));
    else if (view == 6) n = 0.5 + 0.5 * PerlinFbm3Periodic(p, period, octaves, 2, 0.5);
    else if (view == 7) n = PerlinTurbulence3Periodic(p, period, octaves, 2, 0.5);
    else if (view == 8) n = PerlinWorley3Periodic(p, period, octaves, 2, 0.5, 0u);
    else n = ThesisOctavesPeriodic(p, vec3(float(period.x), float(period.y), 256.0), octaves).x;
    return vec4(n, n, n, 1.0);
}

void main() {
    vec2 local = vUV;
    int view = uView, channel = uChannel, octaves = uOctaves;
    bool edge = false;
    if (uLayout != 0) {
        // 2×2 panels, each with the screen's aspect: k = 0 top left, 1 top right, 2, 3 below
        vec2 cell = floor(vUV * 2.0);
        int k = int(cell.x) + 2 * (1 - int(cell.y));
        local = fract(vUV * 2.0);
        vec2 px = fwidth(vUV);
        vec2 d = abs(vUV - 0.5);
        edge = d.x < px.x || d.y < px.y;
        if (uLayout == 1) {
            view = k == 0 ? 6 : k == 1 ? 4 : k == 2 ? 0 : 9;
            channel = 0;
        } else if (uLayout == 2) {
            if (view <= 2) view = 6;
            octaves = k == 0 ? 1 : k == 1 ? 2 : k == 2 ? 4 : 8;
            channel = 0;
        } else {
            if (view != 1) view = 0;
            channel = k;
        }
    }
    // uTiles counts repeats across the screen's height in every layout (a panel is half of it)
    vec2 uv = vec2(local.x * uAspect, local.y) * (uLayout != 0 ? 0.5 * uTiles : uTiles);
    vec3 shown = edge ? vec3(0.02) : Pick(Sample(view, uv, octaves), channel).rgb;
    // noise values are shown as display values: the output's sRGB encoding gives them back
    fragColor = vec4(SrgbToLinear(shown), 1.0);
}
