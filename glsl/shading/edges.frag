#version 330 core
// The screen-space contour composite of the shading lab (spec/003 §2.13 outlines, spec/003
// §2.14: the post-process outline the thesis names as future work), program
// fullscreen("shading/edges"): common/fullscreen.vert + this file. It reads the outline
// G-buffer (gbuffer.frag: view-space normal, linear depth) and writes the outline colour with
// alpha = the outline weight, blended over the image (source alpha, one minus source alpha; the
// image's alpha kept).
//
// uMode 0 Sobel, 1 Roberts cross: an edge where the depth or the normal changes across the
// kernel. The kernel's taps are h = max(1, round(uWidthPx / 2)) pixels from the centre (Sobel's
// 3 × 3 at ±h, Roberts's diagonals at ±h), so the line is about uWidthPx pixels wide, centred on
// the discontinuity.
//   depth    q = (slope of the linear depth per pixel) / (z · uPixelWorld): on a plane whose
//            normal makes the angle θ with the view ray, q = tan θ. The depth threshold is scaled
//            by the view angle — q > uDepthThreshold / max(n·v, 0.02), n the centre pixel's
//            normal — so a plane fires only where sin θ > uDepthThreshold: with a threshold ≥ 1
//            a flat floor seen at a grazing angle never lights up, while a depth step (a
//            silhouette over something farther) has q of order (Δz / z) / (2h · pixel) and does.
//   normal   Δn = |n₁ − n₂| across the kernel > uNormalThreshold (0.4 ≈ a 23° crease).
// uMode 2, 3, 4: the rim silhouettes of spec/003 §2.13 (rim_outline.glsl: threshold, the soft
// staircase of spec/003 eq. 8.4, the 50x²) from the G-buffer's n·v — the surface shader's rim
// term evaluated per pixel, composited the same way.
//
// Failure cases guarded: taps outside the target are clamped to its edge (no wrap-around
// edges); background pixels (depth ≥ half uBackgroundDepth) have n·v = 1 and take the nearer tap
// as the reference depth; the depth is linear, so the relative threshold is the same near and
// far; without uScaleByViewAngle the detector shows the classic failure (a grazing plane lights
// up). A non-finite weight is written as 0. Left as they are: an edge one pixel wide aliases
// (no antialiasing); creases below the normal threshold and depth steps below the depth
// threshold draw nothing.
#include "rim_outline.glsl"

in vec2 vUV;

uniform sampler2D uGBuffer;     // rgb view-space normal, a linear depth (m)
uniform int uMode;              // 0 Sobel, 1 Roberts cross, 2 rim threshold, 3 rim soft, 4 rim 50x²
uniform float uWidthPx;         // line width, pixels
uniform float uDepthThreshold;  // dimensionless slope (see above)
uniform float uNormalThreshold; // |Δn| across the kernel
uniform bool uScaleByViewAngle; // divide the depth threshold by n·v (the fix for grazing planes)
uniform vec2 uTanHalfFov;       // (1 / P[0][0], 1 / P[1][1]): the view ray of a pixel
uniform float uPixelWorld;      // 2 / (P[1][1] · H): a pixel's size at unit depth
uniform float uBackgroundDepth; // the G-buffer's clear depth
uniform float uRim;             // the rim modes' n·v band
uniform vec3 uOutlineColor;     // linear

out vec4 fragColor;

vec4 Tap(ivec2 p, ivec2 o) {
    ivec2 size = textureSize(uGBuffer, 0);
    return texelFetch(uGBuffer, clamp(p + o, ivec2(0), size - 1), 0);
}

bool IsBackground(vec4 g) { return g.a >= 0.5 * uBackgroundDepth; }

void main() {
    ivec2 p = ivec2(gl_FragCoord.xy);
    vec4 c = Tap(p, ivec2(0));
    vec3 ray = vec3((vUV * 2.0 - 1.0) * uTanHalfFov, -1.0);
    float nv = IsBackground(c) ? 1.0 : clamp(dot(c.rgb, -normalize(ray)), 0.0, 1.0);
    float weight = 0.0;
    if (uMode >= 2) {
        weight = IsBackground(c) ? 0.0 : RimOutlineWeight(uMode - 2, nv, uRim);
    } else {
        int h = max(1, int(floor(0.5 * uWidthPx + 0.5)));
        float zRef = c.a;
        float depthSlope;   // depth change per pixel
        float normalDiff;   // |Δn| across the kernel
        if (uMode == 0) {
            vec4 s00 = Tap(p, ivec2(-h, -h)), s10 = Tap(p, ivec2(0, -h));
            vec4 s20 = Tap(p, ivec2(h, -h));
            vec4 s01 = Tap(p, ivec2(-h, 0)), s21 = Tap(p, ivec2(h, 0));
            vec4 s02 = Tap(p, ivec2(-h, h)), s12 = Tap(p, ivec2(0, h)), s22 = Tap(p, ivec2(h, h));
            vec4 gx = (s20 + 2.0 * s21 + s22) - (s00 + 2.0 * s01 + s02);
            vec4 gy = (s02 + 2.0 * s12 + s22) - (s00 + 2.0 * s10 + s20);
            depthSlope = length(vec2(gx.a, gy.a)) / (8.0 * float(h));
            normalDiff = sqrt(dot(gx.rgb, gx.rgb) + dot(gy.rgb, gy.rgb)) / 4.0;
            if (IsBackground(c)) {
                zRef = min(min(min(s00.a, s10.a), min(s20.a, s01.a)),
                           min(min(s21.a, s02.a), min(s12.a, s22.a)));
            }
        } else {
            vec4 a = Tap(p, ivec2(-h, -h)), b = Tap(p, ivec2(h, h));
            vec4 e = Tap(p, ivec2(-h, h)), f = Tap(p, ivec2(h, -h));
            vec4 d1 = b - a, d2 = e - f;
            depthSlope = length(vec2(d1.a, d2.a)) / (2.0 * sqrt(2.0) * float(h));
            normalDiff = sqrt(dot(d1.rgb, d1.rgb) + dot(d2.rgb, d2.rgb)) / sqrt(2.0);
            if (IsBackground(c)) zRef = min(min(a.a, b.a), min(e.a, f.a));
        }
        float q = depthSlope / (max(zRef, 1e-4) * max(uPixelWorld, 1e-8));
        float threshold = uDepthThreshold / (uScaleByViewAngle ? max(nv, 0.02) : 1.0);
        float ratio = max(q / max(threshold, 1e-6), normalDiff / max(uNormalThreshold, 1e-6));
        weight = smoothstep(1.0, 1.25, ratio);
    }
    if (isnan(weight) || isinf(weight)) weight = 0.0;
    fragColor = vec4(uOutlineColor, clamp(weight, 0.0, 1.0));
}
