#version 430
// Finalize pass of the FFT ocean (compute path, GL ≥ 4.3): displacement (λD_x, η, λD_z, J),
// derivatives and foam of one cascade — spec/000 §1.1(d), Jacobian after Tessendorf 2001 §4.4,
// foam as app/sim/ocean.py foam_step.  Equations and guarded failure cases (folds J ≤ 0,
// dt ≤ 0) in ocean_finalize.glsl.  Foam is read and written in place (one texel each).
layout(local_size_x = 8, local_size_y = 8) in;
layout(rgba32f, binding = 0) readonly uniform image2D uFields0;
layout(rgba32f, binding = 1) readonly uniform image2D uFields1;
layout(rgba32f, binding = 2) writeonly uniform image2D uDisp;
layout(rgba32f, binding = 3) writeonly uniform image2D uDeriv;
layout(r32f, binding = 4) uniform image2D uFoam;
uniform int uN;

#include "ocean_finalize.glsl"

void main() {
    ivec2 texel = ivec2(gl_GlobalInvocationID.xy);
    if (texel.x >= uN || texel.y >= uN) return;
    vec4 disp, deriv;
    float foam;
    FinalizeOceanTexel(imageLoad(uFields0, texel), imageLoad(uFields1, texel),
                       imageLoad(uFoam, texel).r, disp, deriv, foam);
    imageStore(uDisp, texel, disp);
    imageStore(uDeriv, texel, deriv);
    imageStore(uFoam, texel, vec4(foam));
}
