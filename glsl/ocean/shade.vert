#version 330 core
// The deferred shading pass's quad over the band of rows uBand (as ocean/band.vert), which also
// reads the sky's light from straight up once per vertex for every pixel's shading
// (OceanSkyAmbient, ocean/shading.glsl: spec/000 §1.2's ambient term of the water body and the
// foam). No equation of its own; failure cases: those of shading.glsl's EnvironmentRadiance.
#define OCEAN_AMBIENT_SOURCE
#include "ocean/shading.glsl"

uniform vec2 uBand;        // NDC y of the band's bottom and top rows' edges
uniform float uBandDepth;  // NDC z of the quad

out vec2 vUV;
flat out vec3 vSkyAmbient;

void main() {
    vec2 p = vec2(float(gl_VertexID & 1), float((gl_VertexID >> 1) & 1));
    vec2 ndc = vec2(p.x * 2.0 - 1.0, mix(uBand.x, uBand.y, p.y));
    vUV = ndc * 0.5 + 0.5;
    vSkyAmbient = OceanSkyAmbient();
    gl_Position = vec4(ndc, uBandDepth, 1.0);
}
