#version 330 core
// Test probe for the shared sea plane (tests/gl/test_sea_plane.py): evaluates the functions of
// glsl/common/sea_plane.glsl at the points of uPoints (one per pixel), so the test compares
// them with the numpy twin app/sim/sea_plane.py.
//   uProbeMode 0: p = view direction: (SeaReflectionDirection(p, uMss), SeaRoughIncidence)
//              1: p = view direction: (SeaHorizonDirection(p), 0)
//              2: p = (n·h, mss, cos θ): (SeaBeckmann(n·h, mss), SchlickFresnel(F0, cos θ), 0, 0)
//              3: p = view direction: (SeaPlaneRadiance(p, …), 0), with a made-up sky:
//                 reflected = 0.2 + 0.5·|r|, horizon = uHorizon + 0.1·|h.x|
#include "../common/sea_plane.glsl"

uniform sampler2D uPoints;
uniform int uProbeMode;
uniform float uMss;
uniform vec3 uHorizon;
uniform vec3 uSkyAmbient;
uniform vec3 uLightDir;
uniform vec3 uLightRadiance;
uniform vec3 uBodyColor;
uniform float uGlitter;
uniform float uEyeHeight;
uniform float uHazeDistance;

out vec4 fragColor;

void main() {
    vec3 p = texelFetch(uPoints, ivec2(gl_FragCoord.xy), 0).xyz;
    if (uProbeMode == 0) {
        fragColor = vec4(SeaReflectionDirection(p, uMss), SeaRoughIncidence(p, uMss));
    } else if (uProbeMode == 1) {
        fragColor = vec4(SeaHorizonDirection(p), 0.0);
    } else if (uProbeMode == 2) {
        fragColor = vec4(SeaBeckmann(p.x, p.y), SchlickFresnel(SEA_F0, p.z), 0.0, 0.0);
    } else {
        vec3 reflected = 0.2 + 0.5 * abs(SeaReflectionDirection(p, uMss));
        vec3 horizon = uHorizon + 0.1 * abs(SeaHorizonDirection(p).x);
        fragColor = vec4(SeaPlaneRadiance(p, reflected, horizon, uSkyAmbient, uLightDir,
                                          uLightRadiance, uBodyColor, uMss, uGlitter,
                                          uEyeHeight, uHazeDistance), 0.0);
    }
}
