#version 330 core
// Compositing a participating-medium layer (both cloud models: spec/001 §1.7 "mixed with the sky
// colour", spec/000 §1.6; the clouds as a separate layer over any scene is beyond the theses):
// RGBA = (in-scattered radiance, premultiplied; view transmittance T), over what the scene
// already drew (app/render/layers.py draws it). The pass runs with blending
// (ONE, SRC_ALPHA) on colour and (ZERO, ONE) on alpha:
//     out.rgb = layer.rgb + layer.a · scene.rgb,   out.a = scene.a
// so where the clouds miss (rgb = 0, T = 1) the scene's value is kept exactly (criteria D2,
// E5), and opaque geometry in front of the clouds was already cut out of the layer by the
// march (it clips its interval at the scene depth).
// Failure cases: none beyond the layer's; a NaN in the layer would spread to the scene, which
// the stability tests rule out.

in vec2 vUV;
out vec4 fragColor;
uniform sampler2D uCloudLayer;

void main() {
    fragColor = texelFetch(uCloudLayer, ivec2(gl_FragCoord.xy), 0);
}
