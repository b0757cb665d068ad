#version 330 core
// =============================================================================================
// The noise lab: one noise function or one baked texture on the screen, tiled 2×2 (or more) so a
// seam would show where the tiles meet. Live functions come from glsl/common/noise_*.glsl
// (Perlin 2002, Worley 1996, fBm, turbulence, Perlin–Worley, the wood thesis's value noise);
// bakes are the cloud shape / detail volumes and the weather map (glsl/bakes/, spec/001 §1.1,
// spec/000 §1.6), shown as a z slice of one channel or as RGB.
// Values are written so that a PNG (clamp tone map) shows them unchanged.
// Views: 0 shape, 1 detail, 2 weather, 3 Perlin, 4 Worley F1, 5 Worley F2 − F1, 6 Perlin fBm,
// 7 turbulence, 8 Perlin–Worley, 9 value noise (thesis).
// Equations: the fBm views are the normalised spec/001 eq. 3.2 (noise_fbm.glsl); the value
// noise is spec/004 §1.5 (noise_value.glsl).
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
uniform int uChannel;      // 0 R, 1 G, 2 B, 3 A, 4 RGB
uniform float uSlice;      // z in [0, 1)
uniform float uTiles;      // how many repeats across the screen's height
uniform float uAspect;
uniform float uScale;      // lattice cells per tile for live functions
uniform int uOctaves;
uniform sampler3D uVolume;
uniform sampler2D uMap;

vec4 Pick(vec4 v) {
    if (uChannel == 4) return vec4(v.rgb, 1.0);
    float c = uChannel == 0 ? v.r : uChannel == 1 ? v.g : uChannel == 2 ? v.b : v.a;
    return vec4(vec3(c), 1.0);
}

void main() {
    vec2 uv = vec2(vUV.x * uAspect, vUV.y) * uTiles;
    vec4 v;
    if (uView <= 1) {
        v = texture(uVolume, vec3(uv, uSlice));
    } else if (uView == 2) {
        v = texture(uMap, uv);
    } else {
        ivec3 period = ivec3(int(uScale));
        vec3 p = vec3(fract(uv), uSlice) * uScale;
        float n;
        if (uView == 3) n = 0.5 + 0.5 * PerlinNoise3Periodic(p, period);
        else if (uView == 4) n = WorleyNoise3Periodic(p, period, 0u).x;
        else if (uView == 5) n = WorleyF2MinusF1(WorleyNoise3Periodic(p, period, 0u));
        else if (uView == 6) n = 0.5 + 0.5 * PerlinFbm3Periodic(p, period, uOctaves, 2, 0.5);
        else if (uView == 7) n = PerlinTurbulence3Periodic(p, period, uOctaves, 2, 0.5);
        else if (uView == 8) n = PerlinWorley3Periodic(p, period, uOctaves, 2, 0.5, 0u);
        else n = ThesisOctaves(p, uOctaves).x;
        v = vec4(n, n, n, 1.0);
    }
    // noise values are shown as display values: the output's sRGB encoding gives them back
    fragColor = vec4(SrgbToLinear(Pick(v).rgb), 1.0);
}
