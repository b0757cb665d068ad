#version 330 core
// A boat's wake as foam (spec/000 §4 item 7, beyond the thesis; Kelvin 1887: wake.glsl, twin
// app/sim/wake.py), evaluated once per block of uWakeStride × uWakeStride screen pixels for the
// deferred ocean: the wake's loop over its trail samples is most of the shading pass's cost on a
// software rasteriser, and its foam is soft (cusp lines and wash bands several pixels wide), so
// shade.frag reads it back from this texture, filtered, instead of looping per pixel.
// Each texel takes the rest point of the first pixel of its block that shows the sea (from the
// deferred inputs, surface_inputs.frag / far_inputs.frag), centre first. The pass is drawn only
// over the screen rectangle of the trail's bounds (a scissor set on the CPU); the rest of the
// texture is cleared to 0.
// Failure cases guarded: a block without sea (the hull, the sky) writes 0, not the foam of a
// point the inputs never set; texel reads are clamped to the inputs' size (the last block of an
// odd-sized screen); no trail samples or a point outside the trail's bounds give 0 after one
// test (WakeFoam).
uniform sampler2D uInputSurf;  // (rest point − camera.xz, footprint, kind: 0 none, 1 mesh, 2 far)
uniform int uWakeStride;       // screen pixels per texel side

out vec4 fragColor;

#include "wake.glsl"

void main() {
    ivec2 size = textureSize(uInputSurf, 0);
    ivec2 base = ivec2(gl_FragCoord.xy) * uWakeStride;
    int h = uWakeStride / 2;
    ivec2 order[4] = ivec2[4](ivec2(h, h), ivec2(0, 0), ivec2(uWakeStride - 1, 0),
                              ivec2(0, uWakeStride - 1));
    vec4 s = vec4(0.0);
    for (int i = 0; i < 4; ++i) {
        vec4 t = texelFetch(uInputSurf, min(base + order[i], size - 1), 0);
        if (s.w < 0.5 && t.w > 0.5) s = t;
    }
    fragColor = vec4(s.w > 0.5 ? WakeFoam(s.xy) : 0.0);
}
