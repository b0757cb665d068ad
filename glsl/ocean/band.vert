#version 330 core
// A band of screen rows for the ocean's deferred passes (spec/000 §1.1–1.2): the far plane's
// inputs are drawn only over the rows between the horizon and where the mesh ends (computed from
// the camera by app/effects/ocean/deferred.py), and the shading pass over the whole screen on the
// far plane, where its depth test keeps only the pixels the sea covered. Four vertices, a
// triangle strip; vUV is (0,0) bottom-left to (1,1) top-right of the screen, as
// common/fullscreen.vert gives it.
// Equations: none of the thesis's; the band's rows are NDC heights uBand = (bottom, top).
// Failure cases guarded: an empty band is never drawn (the CPU skips it); rows are given in
// NDC and clamped to the screen by the CPU, so the quad never leaves the clip volume sideways;
// uBandDepth = 1 (the far plane) is inside the clip volume (−w ≤ z ≤ w), for the shading pass's
// depth test against the cleared depth.
// With OCEAN_AMBIENT_VARYING (the shading pass) it also reads the sky's light from straight up
// once per vertex, for every pixel's shading (OceanSkyAmbient, ocean/shading.glsl).
uniform vec2 uBand;        // NDC y of the band's bottom and top rows' edges
uniform float uBandDepth;  // NDC z of the quad

out vec2 vUV;

#ifdef OCEAN_AMBIENT_VARYING
#define OCEAN_AMBIENT_SOURCE
#include "ocean/shading.glsl"
flat out vec3 vSkyAmbient;
#endif

void main() {
    vec2 p = vec2(float(gl_VertexID & 1), float((gl_VertexID >> 1) & 1));
    vec2 ndc = vec2(p.x * 2.0 - 1.0, mix(uBand.x, uBand.y, p.y));
    vUV = ndc * 0.5 + 0.5;
#ifdef OCEAN_AMBIENT_VARYING
    vSkyAmbient = OceanSkyAmbient();
#endif
    gl_Position = vec4(ndc, uBandDepth, 1.0);
}
