#version 330 core
// Test probe for Cloud Model B (used by the Model B tests): evaluates the functions of
// glsl/clouds_b/clouds_b_model.glsl at the points of uPoints (one per pixel), so the tests
// compare them with the numpy twins in app/sim/clouds_b.py.
//   uProbeMode 0: (CloudsBSampleDensity(p), envelope = height gradient · edge weight, 0, 0)
//              1: (CloudsBLightAtPos(p, uProbeDir), 0, 0, 0)
//              2: (CloudsBRayBoxDistance(uBoundsMin, uBoundsMax, p, uProbeDir), 0, 0)
//              3: p = (cos θ, g, d): (HG(cos θ, g), phase(cos θ), Beer(d), Powder(d))
#include "../clouds_b/clouds_b_model.glsl"

uniform sampler2D uPoints;
uniform int uProbeMode;
uniform vec3 uProbeDir;

out vec4 fragColor;

void main() {
    vec3 p = texelFetch(uPoints, ivec2(gl_FragCoord.xy), 0).xyz;
    if (uProbeMode == 0) {
        vec3 size = uBoundsMax - uBoundsMin;
        float h = (p.y - uBoundsMin.y) / size.y;
        float envelope = CloudsBHeightGradient(h, CloudsBCoverage(p)) * CloudsBEdgeWeight(p);
        fragColor = vec4(CloudsBSampleDensity(p), envelope, 0.0, 0.0);
    } else if (uProbeMode == 1) {
        fragColor = vec4(CloudsBLightAtPos(p, uProbeDir), 0.0, 0.0, 0.0);
    } else if (uProbeMode == 2) {
        fragColor = vec4(CloudsBRayBoxDistance(uBoundsMin, uBoundsMax, p, uProbeDir), 0.0, 0.0);
    } else {
        fragColor = vec4(HenyeyGreenstein(p.x, p.y), CloudsBPhase(p.x), CloudsBBeer(p.z),
                         CloudsBPowder(p.z));
    }
}
