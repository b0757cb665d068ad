// The wood's distortion noise over the object box [-0.5, 0.5]³, for baking into a 3D texture
// (bench: baked lookup against per-pixel noise). uvw is a texel centre in [0, 1]³.
// Source: the distortion input of the thesis's wood, octaves(noiseCoords, RecDepth)
// (spec/004 §1.4, §1.6), with the noise chosen by the "noise" switch (material_noise.glsl);
// its stages are wood_noise_bake.comp (compute) and wood_noise_bake.frag (one slice per pass).
// Failure cases: noise finer than a texel is lost (the texture is sampled trilinearly; the
// bench measures the error against the per-pixel noise); points outside the box clamp to its
// faces; the alpha channel is a constant 1.
#include "material_noise.glsl"
#include "wood.glsl"

vec4 BakeValue(vec3 uvw) {
    return vec4(MaterialNoise3(WoodNoiseCoords(uvw - 0.5), uRecDepth), 1.0);
}
