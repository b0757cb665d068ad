#version 330 core
// The village's toon contours (spec/003 §2.13 contours, §2.14: the post-process outline the
// thesis names as future work, after its geometry-shader shell and rim silhouettes failed on the
// low-poly village), program fullscreen("village/contours"): common/fullscreen.vert + this
// file. Drawn in the opaque stage right after the village's surfaces and before the grass (whose
// thousands of blades would otherwise all be outlined), over the image, blended (source alpha,
// one minus source alpha), from a copy of the image's depth.
//
// The detector: w = 1/z (z the view depth) is affine in screen space across any plane, so its
// discrete Laplacian L = Σ w(neighbours at ±h) − 4·w(centre) is 0 on every flat face whatever
// the angle it is seen at (a grazing ground never lights up), and large where the depth jumps (a
// silhouette over something farther) or folds (a convex edge: a roof's ridge, a house's corner).
// With the GL depth d, w = (1 − d)/n + d/f is itself affine in d, so L_w = (1/f − 1/n)·L_d. The
// line lies on the nearer side only (L_w < 0 there: the neighbours are farther), one pixel of the
// object, and its weight is relative — q = −L_w / w_centre, ≈ 1 − z_near/z_far at a silhouette —
// so a near prop and a far house are outlined alike, and a small depth step (a stone on the
// ground) is not: weight = smoothstep(uContourThreshold, 2·uContourThreshold, q).
// The line's colour takes the global fog of its own distance (fog.glsl: the distance fog's
// factor of spec/003 eq. 7.24, spec/003 eq. 7.27, spec/003 eq. 7.28, spec/003 eq. 7.29, or the
// height fog's transmittance), so far lines fade into the fog with what they outline.
// Failure cases guarded: taps clamped to the image (no wrap-around lines at its border); the
// background (d = 1: the sky, the far plane) is never outlined itself; w kept above 0; a
// non-finite weight gives no line.
#include "fog.glsl"

in vec2 vUV;

uniform sampler2D uDepth;            // a copy of the image's depth (GL window depth, 0..1)
uniform vec2 uNearFar;               // the camera's near and far planes [m]
uniform mat4 uInvViewProj;           // clip → world, for the fog of the line's own distance
uniform int uTap;                    // the taps' distance h [px] (the line's width)
uniform float uContourThreshold; // @param 0.06 [0.005, 1] step=0.005 §2.13 contours: the relative
                                 // depth step (≈ 1 − z_near/z_far) where a line begins; twice it is
                                 // a full line
uniform float uContourStrength; // @param 0.85 [0, 1] step=0.01 §2.13 contours: the line's opacity
uniform vec3 uContourColor; // @param (0.05, 0.035, 0.03) [0, 1] color §2.13 contours: the line's
                            // colour (linear), a warm near-black

out vec4 fragColor;

float DepthAt(ivec2 p) {
    ivec2 size = textureSize(uDepth, 0);
    return texelFetch(uDepth, clamp(p, ivec2(0), size - 1), 0).r;
}

// 1/z from the GL depth d (affine in d)
float InverseDepth(float d, vec2 nf) {
    return max((1.0 - d) / nf.x + d / nf.y, 1e-9);
}

void main() {
    ivec2 p = ivec2(gl_FragCoord.xy);
    float d = DepthAt(p);
    if (d >= 1.0) discard;  // the background is never outlined itself
    vec2 nf = vec2(max(uNearFar.x, 1e-6), max(uNearFar.y, uNearFar.x + 1e-3));
    int h = max(uTap, 1);
    float sum = DepthAt(p + ivec2(h, 0)) + DepthAt(p - ivec2(h, 0))
                + DepthAt(p + ivec2(0, h)) + DepthAt(p - ivec2(0, h));
    float lapD = sum - 4.0 * d;
    float w = InverseDepth(d, nf);
    float q = -(1.0 / nf.y - 1.0 / nf.x) * lapD / w;  // −L_w / w
    float t = max(uContourThreshold, 1e-4);
    float weight = smoothstep(t, 2.0 * t, q) * clamp(uContourStrength, 0.0, 1.0);
    if (!(weight > 0.0) || isinf(weight)) discard;
    vec4 world = uInvViewProj * vec4(vUV * 2.0 - 1.0, d * 2.0 - 1.0, 1.0);
    vec3 pos = world.xyz / world.w;
    vec3 colour = max(uContourColor, vec3(0.0));
    float f = 1.0;
    if (uFogHeight) {
        f = FogHeightTransmittance(pos);
    } else if (uFogMode != 0) {
        f = FogFactor(FogDistance(1.0 / w, uFogNearFar));
    }
    fragColor = vec4(mix(uFogColor, colour, f), weight);
}
