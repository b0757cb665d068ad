// The wood's distortion noise over the object box [-0.5, 0.5]³, for baking into a 3D texture
// (bench: baked lookup against per-pixel noise). uvw is a texel centre in [0, 1]³.
#include "material_noise.glsl"
#include "wood.glsl"

vec4 BakeValue(vec3 uvw) {
    return vec4(MaterialNoise3(WoodNoiseCoords(uvw - 0.5), uRecDepth), 1.0);
}
