#version 330 core
// Test probe for bump and parallax mapping (tests/gl/test_shading_maps.py): evaluates the
// functions of glsl/common/bump.glsl and glsl/common/parallax.glsl (spec/003 §2.2, §2.3) at
// the points of uPoints (one per pixel), so the test compares them with the numpy twins
// app/sim/bump.py and app/sim/parallax.py.
//   uProbeMode 0: p = (u, v, 0): (BumpedNormal(uNormalMap, p.xy, uVertexNormal, uTangent), 0)
//              1: p = (u, v, 0): (ParallaxUV(uHeightMap, p.xy, uViewTS), 0, 0)
//              2: p = a world direction to the eye: (TangentSpaceView(p, frame), 0), the frame
//                 BumpTangentFrame(uVertexNormal, uTangent)
// Failure cases: none of its own — those guarded are the included files' (their headers).
#include "../common/parallax.glsl"

uniform sampler2D uPoints;
uniform sampler2D uNormalMap;
uniform sampler2D uHeightMap;
uniform int uProbeMode;
uniform vec3 uVertexNormal;
uniform vec4 uTangent;
uniform vec3 uViewTS;

out vec4 fragColor;

void main() {
    vec3 p = texelFetch(uPoints, ivec2(gl_FragCoord.xy), 0).xyz;
    if (uProbeMode == 0) {
        fragColor = vec4(BumpedNormal(uNormalMap, p.xy, uVertexNormal, uTangent), 0.0);
    } else if (uProbeMode == 1) {
        fragColor = vec4(ParallaxUV(uHeightMap, p.xy, uViewTS), 0.0, 0.0);
    } else {
        fragColor = vec4(TangentSpaceView(p, BumpTangentFrame(uVertexNormal, uTangent)), 0.0);
    }
}
