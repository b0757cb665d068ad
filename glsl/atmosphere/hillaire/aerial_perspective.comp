#version 430 core
// =============================================================================================
// Method 4, pass 4 (compute, GL ≥ 4.3) — the aerial-perspective volume, when the camera or the
// sun moved (Hillaire 2020 §5.4). One invocation per froxel column marches the camera ray once
// and stores all slices into two RGBA32F 3D images. Model, layout and failure cases:
// aerial_perspective.glsl. The fragment fallback is aerial_perspective.frag.
// =============================================================================================
layout(local_size_x = 8, local_size_y = 8, local_size_z = 1) in;
layout(rgba32f, binding = 0) writeonly uniform image3D uHillaireApImage0;
layout(rgba32f, binding = 1) writeonly uniform image3D uHillaireApImage1;

#include "hillaire_common.glsl"
#include "camera.glsl"

// Every slice of the column goes into the two images (aerial_perspective.glsl's HILLAIRE_AP_STORE).
void HillaireApStore(ivec3 p, vec4 a, vec4 b) {
    imageStore(uHillaireApImage0, p, a);
    imageStore(uHillaireApImage1, p, b);
}
#define HILLAIRE_AP_STORE(p, a, b) HillaireApStore(p, a, b)
#include "aerial_perspective.glsl"

void main() {
    ivec2 texel = ivec2(gl_GlobalInvocationID.xy);
    if (any(greaterThanEqual(texel, uHillaireApSize.xy))) return;
    vec4 a, b;
    HillaireApColumn(texel, -1, a, b);
}
