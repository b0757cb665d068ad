#version 330 core
// Weighted blended OIT, the composite (McGuire and Bavoil 2013): full-screen pass
// ProgramSpec("surfaces/oit_composite", fullscreen vertex stage) over the opaque image with
// Blend SrcAlpha OneMinusSrcAlpha:
//   C = Σ c·α·w / Σ α·w · (1 − Π (1 − α)) + C₀ · Π (1 − α)        (McGuire 2013 eq. 6)
// uAccum: .rgb Σ c·α·w, .a the coverage 1 − Π (1 − α) (cleared to 0); uWeightSum: .r Σ α·w.
// With SAMPLES > 0 the targets are multisampled: the premultiplied result and the coverage
// are averaged over the samples (one fragment per pixel writes every sample).
// Failure cases guarded: Σ α·w = 0 (nothing drawn, or α = 0 everywhere) divides by max(·, 1e-5)
// and a pixel with coverage 0 is discarded (the image is untouched); Inf/NaN from an
// overflowed half float are clamped to the half range, so no NaN reaches the image.
#ifndef SAMPLES
#define SAMPLES 0
#endif

in vec2 vUV;
out vec4 fragColor;

#if SAMPLES > 0
uniform sampler2DMS uAccum;
uniform sampler2DMS uWeightSum;
#else
uniform sampler2D uAccum;
uniform sampler2D uWeightSum;
#endif

vec4 resolveOne(vec4 accum, float wsum) {
    vec3 rgb = clamp(accum.rgb, vec3(0.0), vec3(65504.0));
    if (any(isnan(rgb))) rgb = vec3(0.0);
    float cover = clamp(accum.a, 0.0, 1.0);
    if (isnan(cover)) cover = 0.0;
    vec3 mean = rgb / max(clamp(wsum, 0.0, 65504.0), 1e-5);
    return vec4(mean * cover, cover);  // premultiplied
}

void main() {
    ivec2 px = ivec2(gl_FragCoord.xy);
#if SAMPLES > 0
    vec4 sum = vec4(0.0);
    for (int s = 0; s < SAMPLES; ++s) {
        sum += resolveOne(texelFetch(uAccum, px, s), texelFetch(uWeightSum, px, s).r);
    }
    vec4 premul = sum / float(SAMPLES);
#else
    vec4 premul = resolveOne(texelFetch(uAccum, px, 0), texelFetch(uWeightSum, px, 0).r);
#endif
    if (premul.a <= 1e-6) discard;
    fragColor = vec4(premul.rgb / premul.a, premul.a);
}
