#version 330 core
// Test probe: evaluates the thesis's value noise at the points stored in uPoints (one per
// pixel, RGB = x, y, z) and writes the result; the value-noise tests compare it with the
// numpy twin (app/sim/noise/value.py). PROBE_DEPTH = 0 evaluates noise3, d ≥ 1 evaluates
// octaves(p, d); PROBE_PIXEL evaluates getPixel at integer points.
#include "noise_value.glsl"

out vec4 fragColor;
uniform sampler2D uPoints;
uniform int uDepth;

void main() {
    vec3 p = texelFetch(uPoints, ivec2(gl_FragCoord.xy), 0).xyz;
#ifdef PROBE_PIXEL
    fragColor = vec4(ThesisGetPixel(p), 1.0);
#else
    fragColor = vec4(uDepth == 0 ? ThesisNoise3(p) : ThesisOctaves(p, uDepth), 1.0);
#endif
}
