#version 330 core
// Depth peeling (the exact reference of spec/003 §2.4's blended layers; Everitt 2001): the
// full-screen pass ProgramSpec("surfaces/peel_composite", fullscreen vertex stage) that copies
// a premultiplied (c·α, α) image. The CPU blends it two ways: each peeled layer under the
// accumulated front layers (Blend OneMinusDstAlpha One: C += (1 − A)·c·α, A += (1 − A)·α),
// then the accumulation over the opaque image (Blend One OneMinusSrcAlpha).
// Failure cases guarded: texelFetch (no filtering across pixels); a pixel with no coverage is
// discarded so the image below is untouched; NaN is replaced by nothing drawn.
in vec2 vUV;
out vec4 fragColor;

uniform sampler2D uLayer;

void main() {
    vec4 c = texelFetch(uLayer, ivec2(gl_FragCoord.xy), 0);
    if (any(isnan(c))) discard;
    if (c.a <= 0.0 && all(lessThanEqual(c.rgb, vec3(0.0)))) discard;
    fragColor = c;
}
