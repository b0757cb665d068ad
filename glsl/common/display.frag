#version 330 core
// Display pass: HDR scene radiance → tone-mapped, sRGB-encoded 8-bit window pixels, enlarged to
// the window when dynamic resolution renders the scene smaller (app/ui/resolution.py): bilinear
// (the texture's own filter), or Catmull-Rom bicubic in five bilinear taps — the 4 × 4 kernel's
// cross, its four corners dropped and the weights renormalised (Jimenez 2016, the Filmic SMAA
// course's TAA resolve).
// Failure cases guarded: NaN or Inf radiance is shown as magenta rather than spread over the
// screen by the filter; the kernel's negative lobes cannot make radiance negative (clamped to 0
// before the tone map); taps beyond the image's border read its edge (the window clamps the
// texture's wrap), never the opposite side.
#include "tonemap.glsl"

in vec2 vUV;
out vec4 fragColor;

uniform sampler2D uScene;
uniform float uExposure;
uniform int uTonemap;
uniform int uBicubic;  // 1: Catmull-Rom enlargement; 0: the texture's own (bilinear) filter

// Catmull-Rom bicubic of tex at uv ([0, 1]²) in five bilinear taps (Jimenez 2016): each axis's
// two middle weights w1 + w2 merge into one bilinear tap at their centroid; of the 4 × 4
// kernel only the cross is read (centre, left, right, down, up) and the weights are
// renormalised over it, so a flat image stays flat. Linear radiance in, out; the negative
// lobes may overshoot below 0, which main clamps.
vec3 CatmullRom5(sampler2D tex, vec2 uv) {
    vec2 size = vec2(textureSize(tex, 0));
    vec2 pos = uv * size;
    vec2 centre = floor(pos - 0.5) + 0.5;  // the texel centre at or left of/below pos
    vec2 f = pos - centre;
    vec2 w0 = f * (-0.5 + f * (1.0 - 0.5 * f));
    vec2 w1 = 1.0 + f * f * (-2.5 + 1.5 * f);
    vec2 w2 = f * (0.5 + f * (2.0 - 1.5 * f));
    vec2 w3 = f * f * (-0.5 + 0.5 * f);
    vec2 w12 = w1 + w2;  // the two middle texels in one bilinear tap
    vec2 t0 = (centre - 1.0) / size;
    vec2 t3 = (centre + 2.0) / size;
    vec2 t12 = (centre + w2 / w12) / size;
    float wc = w12.x * w12.y;
    float wl = w0.x * w12.y, wr = w3.x * w12.y, wd = w12.x * w0.y, wu = w12.x * w3.y;
    vec3 sum = texture(tex, t12).rgb * wc
             + texture(tex, vec2(t0.x, t12.y)).rgb * wl + texture(tex, vec2(t3.x, t12.y)).rgb * wr
             + texture(tex, vec2(t12.x, t0.y)).rgb * wd + texture(tex, vec2(t12.x, t3.y)).rgb * wu;
    return sum / (wc + wl + wr + wd + wu);
}

void main() {
    vec3 radiance = uBicubic == 1 ? CatmullRom5(uScene, vUV) : texture(uScene, vUV).rgb;
    // NaN/Inf must not spread over the screen through filtering: show them as magenta.
    if (any(isnan(radiance)) || any(isinf(radiance))) {
        fragColor = vec4(1.0, 0.0, 1.0, 1.0);
        return;
    }
    fragColor = vec4(LinearToSrgb(Tonemap(max(radiance, vec3(0.0)), uExposure, uTonemap)), 1.0);
}
