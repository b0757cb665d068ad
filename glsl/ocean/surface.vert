#version 330 core
// Ocean surface mesh (spec/000 §1.1–1.2): a polar grid centred under the camera, rings spaced
// geometrically so cells stay about square and shrink on screen evenly with distance (level of
// detail without seams or T-junctions: one connected mesh). Each vertex is a rest point; the wave
// model displaces it (waves.glsl), with a texture mip level matched to the vertex spacing so the
// geometry does not alias, fading to flat water at uFadeEnd where the analytic far plane
// (far.frag) takes over to the horizon. Positions stay camera-relative (float32 at any distance).
// Equations (in waves.glsl): the sine height of spec/000 §1.1(a), the Gerstner position
// spec/000 eq. 2.5, the FFT displacement of spec/000 eq. 2.11 with its choppy terms (§1.1(d)).
// Failure cases guarded: geometric aliasing of short waves (the displacement is read at a mip
// level matched to the vertex spacing in_polar.z); float32 precision far from the origin
// (camera-relative positions, absolute phases folded on the CPU in float64); a seam against
// the far plane (displacement faded to flat water by uFadeEnd); cracks and T-junctions (one
// connected polar mesh).
in vec3 in_polar;  // (radius m, angle rad, vertex spacing m)

uniform mat4 uViewProjRel;   // view-projection of camera-relative positions
uniform vec3 uCameraPos;

out vec2 vOff;       // rest point − camera.xz
out vec3 vRel;       // displaced point − camera
out float vHeight;   // η at the vertex (m)

#include "ocean/waves.glsl"

void main() {
    vec2 off = in_polar.x * vec2(cos(in_polar.y), sin(in_polar.y));
    vec3 d = OceanDisplacement(off, in_polar.z);
    vOff = off;
    vHeight = d.y;
    vRel = vec3(off.x + d.x, d.y - uCameraPos.y, off.y + d.z);
    gl_Position = uViewProjRel * vec4(vRel, 1.0);
}
