#version 330 core
// The alpha quads of the surfaces lab (spec/003 §2.4 transparency; weighted blended OIT of
// McGuire and Bavoil 2013), program ProgramSpec("surfaces/alpha"): alpha.vert + this file.
// Lit as albedo × texture × (ambient + radiance · max(n·l, 0)), two-sided (n turned toward the
// viewer); alpha = texture alpha × uOpacity. uMode picks what the fragment does:
//   0 opaque            alpha ignored, written as 1
//   1 cutout            clip(alpha − Cutoff): discarded when alpha − uCutoff < 0 (Cutoff 0
//                       keeps everything, Cutoff 1 discards every alpha < 1)
//   2 alpha-test-naive  `if (alpha == 0) discard`: alpha just above 0 survives (the stray
//                       fragments of the thesis's Fig. 42c)
//   3 alpha-to-coverage colour with its alpha; the CPU enables GL_SAMPLE_ALPHA_TO_COVERAGE on
//                       a multisampled target (AlphaToMask On), an MSAA mask ∝ alpha
//   4 blend             straight (colour, alpha) for Blend SrcAlpha OneMinusSrcAlpha (the CPU
//                       sets the blend and whether depth is written)
//   5 WBOIT accumulate  location 0: (c·α·w, α) with colour blend One One and alpha blend
//                       OneMinusDstAlpha One, so .rgb = Σ c·α·w and .a = 1 − Π (1 − α) (the
//                       coverage, one minus the revealage; every target clears to 0);
//                       location 1: α·w (One One: Σ α·w); w = w(z, α) of
//                       McGuire 2013 eq. 7 (uWeight 0), McGuire 2013 eq. 8 (1),
//                       McGuire 2013 eq. 9 (2) or McGuire 2013 eq. 10 (3)
//   6 depth-peel layer  premultiplied (c·α, α) of the nearest fragment behind the previous
//                       layer (uPrevDepth, strictly greater) and in front of the opaque depth
//                       (uOpaqueDepth); the depth test LESS of the pass picks the nearest
// Failure cases guarded: the interpolated normal is re-normalised with a fallback for a zero
// vector (camera in the quad's plane: n·v = 0 picks the front side); alpha is clamped to
// [0, 1]; the depth weight is clamped as in the paper (1e-2 … 3e3) and |z| is kept finite, so
// no Inf reaches the RGBA16F accumulation; depth textures are read with texelFetch (no
// filtering, no comparison); OPAQUE_MS reads sample 0 of a multisampled opaque depth.
#ifndef OPAQUE_MS
#define OPAQUE_MS 0
#endif

in vec3 vWorldPos;
in vec3 vNormal;
in vec2 vUV;
in float vViewDepth;

uniform int uMode;
uniform vec3 uAlbedo;       // linear
uniform float uOpacity;     // multiplies the texture's alpha
uniform sampler2D uAlphaMap;  // rgb tints the albedo, a the alpha
uniform float uCutoff;
uniform vec3 uCameraPos;
uniform vec3 uLightDir;     // toward the light
uniform vec3 uRadiance;
uniform vec3 uAmbient;
uniform int uWeight;        // which depth weight (mode 5)
uniform bool uFirstLayer;   // mode 6: no previous layer
uniform sampler2D uPrevDepth;
#if OPAQUE_MS
uniform sampler2DMS uOpaqueDepth;
#else
uniform sampler2D uOpaqueDepth;
#endif

layout(location = 0) out vec4 fragColor;
layout(location = 1) out vec4 fragWeight;

vec3 quadRadiance(vec4 tex) {
    vec3 n = vNormal;
    float len = length(n);
    n = len > 1e-8 ? n / len : vec3(0.0, 0.0, 1.0);
    vec3 v = uCameraPos - vWorldPos;
    if (dot(n, v) < 0.0) n = -n;  // two-sided
    float ndl = max(dot(n, uLightDir), 0.0);
    return uAlbedo * tex.rgb * (uAmbient + uRadiance * ndl);
}

// McGuire 2013 eq. 7
float weightEq7(float z) { return 10.0 / (1e-5 + pow(z / 5.0, 2.0) + pow(z / 200.0, 6.0)); }
// McGuire 2013 eq. 8
float weightEq8(float z) { return 10.0 / (1e-5 + pow(z / 10.0, 3.0) + pow(z / 200.0, 6.0)); }
// McGuire 2013 eq. 9
float weightEq9(float z) { return 0.03 / (1e-5 + pow(z / 200.0, 4.0)); }

float depthWeight(float z, float alpha) {
    z = clamp(abs(z), 0.0, 1e6);
    if (uWeight == 3) {  // McGuire 2013 eq. 10
        float d = clamp(gl_FragCoord.z, 0.0, 1.0);
        return alpha * max(1e-2, 3e3 * pow(1.0 - d, 3.0));
    }
    float w = uWeight == 0 ? weightEq7(z) : (uWeight == 1 ? weightEq8(z) : weightEq9(z));
    return alpha * clamp(w, 1e-2, 3e3);
}

void main() {
    vec4 tex = texture(uAlphaMap, vUV);
    float alpha = clamp(tex.a * uOpacity, 0.0, 1.0);
    vec3 c = quadRadiance(tex);
    fragWeight = vec4(0.0);
    if (uMode == 1) {
        if (alpha - uCutoff < 0.0) discard;  // clip(alpha − Cutoff)
        fragColor = vec4(c, 1.0);
    } else if (uMode == 2) {
        if (alpha == 0.0) discard;
        fragColor = vec4(c, 1.0);
    } else if (uMode == 3 || uMode == 4) {
        fragColor = vec4(c, alpha);
    } else if (uMode == 5) {
        float w = depthWeight(vViewDepth, alpha);
        fragColor = vec4(c * alpha * w, alpha);
        fragWeight = vec4(alpha * w, 0.0, 0.0, 1.0);
    } else if (uMode == 6) {
        ivec2 px = ivec2(gl_FragCoord.xy);
        float opaque = texelFetch(uOpaqueDepth, px, 0).r;  // sample 0 when multisampled
        if (gl_FragCoord.z >= opaque) discard;
        if (!uFirstLayer && gl_FragCoord.z <= texelFetch(uPrevDepth, px, 0).r) discard;
        fragColor = vec4(c * alpha, alpha);
    } else {
        fragColor = vec4(c, 1.0);
    }
}
