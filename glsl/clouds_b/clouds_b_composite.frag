#version 330 core
// Cloud Model B, composite (spec/000 §1.6, A.8): passes the cloud layer (rgb = in-scattered
// light, a = transmittance) to the blender, which computes target = target·a + rgb
// (blend function ONE, SRC_ALPHA on colour; the target's alpha is kept). Reading the layer
// here instead of the target avoids sampling the texture being written.
uniform sampler2D uCloudLayer;

out vec4 fragColor;

void main() {
    fragColor = texelFetch(uCloudLayer, ivec2(gl_FragCoord.xy), 0);
}
