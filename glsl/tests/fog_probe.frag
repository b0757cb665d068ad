#version 330 core
// Test probe for the fog (tests/gl/test_fog.py): evaluates the functions of glsl/common/fog.glsl
// (spec/003 §2.11 b: spec/003 eq. 7.24, spec/003 eq. 7.27, spec/003 eq. 7.28, spec/003 eq. 7.29;
// Quílez 2010) and glsl/fog/plane.glsl (§2.11 a) at the points of uPoints (one per pixel), so
// the test compares them with the numpy twins of app/sim/fog.py.
//   uProbeMode 0: p.x = a view depth w: (FogDistance, FogUnityClipZ, FogFactor of the distance,
//                 FogVertexFactor of a clip position with that w)
//              1: p = a world point: (FogHeightTransmittance(p), FogHeightOpticalDepth(p), 0, 0)
//              2: p = (texture alpha, _Cutoff, time): (FogPlaneCutoff, FogPlaneAlpha, 0, 0)
// Failure cases: none of its own — those guarded are the included files' (their headers).
#include "../common/fog.glsl"
#include "../fog/plane.glsl"

uniform sampler2D uPoints;
uniform int uProbeMode;

out vec4 fragColor;

void main() {
    vec3 p = texelFetch(uPoints, ivec2(gl_FragCoord.xy), 0).xyz;
    if (uProbeMode == 0) {
        float d = FogDistance(p.x, uFogNearFar);
        fragColor = vec4(d, FogUnityClipZ(p.x, uFogNearFar), FogFactor(d),
                         FogVertexFactor(vec4(0.0, 0.0, 0.0, p.x)));
    } else if (uProbeMode == 1) {
        fragColor = vec4(FogHeightTransmittance(p), FogHeightOpticalDepth(p), 0.0, 0.0);
    } else {
        float c = FogPlaneCutoff(p.y, p.z);
        fragColor = vec4(c, FogPlaneAlpha(p.x, c, 1.0), 0.0, 0.0);
    }
}
