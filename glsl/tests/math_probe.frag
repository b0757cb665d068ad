#version 330 core
// Test probe for glsl/common/math.glsl (tests/gl/test_maths_twin.py): evaluates its helpers at
// the points of uPoints (one per pixel), so the test compares them with the numpy twins of
// app/sim/maths.py.
//   uProbeMode 0: p = (x, e0, e1): (smoothstep(e0, e1, x), SmoothStepDown(e1, e0, x),
//                 saturate(x), 0)
//              1: p = a vector: (SafeNormalize(p, (0, 1, 0)), 0)
//              2: p.x = a compass angle [degrees]: (sin a, −cos a, PI, TWO_PI)
// Failure cases: none of its own — those guarded are math.glsl's (its comments).
#include "../common/math.glsl"

uniform sampler2D uPoints;
uniform int uProbeMode;

out vec4 fragColor;

void main() {
    vec3 p = texelFetch(uPoints, ivec2(gl_FragCoord.xy), 0).xyz;
    if (uProbeMode == 0) {
        fragColor = vec4(smoothstep(p.y, p.z, p.x), SmoothStepDown(p.z, p.y, p.x), saturate(p.x),
                         0.0);
    } else if (uProbeMode == 1) {
        fragColor = vec4(SafeNormalize(p, vec3(0.0, 1.0, 0.0)), 0.0);
    } else {
        float a = radians(p.x);
        fragColor = vec4(sin(a), -cos(a), PI, TWO_PI);
    }
}
