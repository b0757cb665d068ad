#version 330 core
// Underwater view (spec/000 §1.2, the thesis's change 1: "underwater clarity" fog while the
// camera is submerged). Per pixel, not per frame: a pixel is under water when its ray starts
// (on the near plane) below the water height there (waves.glsl, §1.3 inversion), so a camera
// exactly at the surface shows the waterline across the image. Under water, light along the ray
// is attenuated per channel over the distance to the first surface (from the depth buffer; the
// open deep has no end, so it is all fog) and replaced by the water's inscattered light:
//   L = L_scene·e^{−σd} + L_water·(1 − e^{−σd}), σ = 3/visibility·(absorption ratios)
// (shading.glsl: UnderwaterExtinction, UnderwaterLight).
// Guards: depth 1 (nothing drawn) → d = ∞ handled as full fog without inf·0.
in vec2 vUV;

uniform sampler2D uColor;       // the target so far (a copy)
uniform sampler2D uSceneDepth;  // window depth in [0, 1], compare mode off

out vec4 fragColor;

#include "camera.glsl"
#include "ocean/waves.glsl"
#include "ocean/shading.glsl"

void main() {
    vec3 color = texture(uColor, vUV).rgb;
    if (!OceanPixelStartsUnderwater(vUV * 2.0 - 1.0, uCameraPos.y)) {
        fragColor = vec4(color, 1.0);
        return;
    }
    float depth = texture(uSceneDepth, vUV).r;
    vec3 trans = vec3(0.0);
    if (depth < 1.0) {
        vec4 p = uInvViewProjRel * vec4(vec3(vUV, depth) * 2.0 - 1.0, 1.0);
        float d = length(p.xyz / p.w);
        trans = exp(-UnderwaterExtinction() * d);
    }
    fragColor = vec4(color * trans + UnderwaterLight() * (1.0 - trans), 1.0);
}
