#version 330 core
// Finalize pass of the FFT ocean (fragment path, GL 3.3): displacement (λD_x, η, λD_z, J),
// derivatives and foam of one cascade through MRT — spec/000 §1.1(d), Jacobian after
// Tessendorf 2001 §4.4, foam as app/sim/ocean.py foam_step.  Equations and guarded failure
// cases (folds J ≤ 0, dt ≤ 0) in ocean_finalize.glsl.  Foam ping-pongs: uFoamBefore is last
// frame's texture, oFoam the other one.
uniform sampler2D uFields0;
uniform sampler2D uFields1;
uniform sampler2D uFoamBefore;
layout(location = 0) out vec4 oDisp;
layout(location = 1) out vec4 oDeriv;
layout(location = 2) out vec4 oFoam;

#include "ocean_finalize.glsl"

void main() {
    ivec2 texel = ivec2(gl_FragCoord.xy);
    float foam;
    FinalizeOceanTexel(texelFetch(uFields0, texel, 0), texelFetch(uFields1, texel, 0),
                       texelFetch(uFoamBefore, texel, 0).r, oDisp, oDeriv, foam);
    oFoam = vec4(foam);
}
