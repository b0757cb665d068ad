#version 330 core
// The toon village's water plane (spec/003 §2.10, the thesis's Custom/Nature/Water): the vertex
// stage. A disc around the camera at the sea level of the frame's terrain, out to the far
// plane's corners in every direction, lifted by the tide along its normal:
//   y = sea level + Tide Height·sin t      (the repository's _TideHeight·_SinTime.w, TideLevel)
// The tide moves the whole plane at once and needs no vertices inside it; the rasteriser's depth
// precision does: a polar grid of doubling rings (app.sim.toon_water.plane_mesh) keeps the
// triangles near the camera small. The global fog, which the thesis computes per vertex, is
// computed per fragment on the water (uFogPerPixel): rings kilometres wide cannot carry it
// (spec/003 eq. 7.24 in glsl/common/fog.glsl).
// Positions are camera-relative (uViewProjRel), so float32 stays exact far from the origin.
// Failure cases guarded: a camera far plane of any size (the plane's reach uExtent follows
// it); a camera exactly in the plane (the plane degenerates to a line and draws nothing; the
// underwater pass covers the pixels below the surface); the fog factor of a vertex behind the
// camera (fog.glsl clamps w ≤ 0).
#include "water.glsl"
#include "fog.glsl"

in vec2 in_xz;                // the grid's vertices in units of uExtent

uniform mat4 uViewProjRel;    // projection × view for camera-relative positions
uniform vec3 uCameraPos;      // world position of the camera [m]
uniform float uSeaLevel;      // the terrain's sea level [m]
uniform float uTime;          // seconds since the scene started
uniform float uExtent;        // the plane's reach [m] (far · the corner rays' reach)

out vec4 vWorldPos;           // world position, the global fog's per-vertex factor in w
out vec3 vRel;                // position relative to the camera [m]

void main() {
    float level = TideLevel(uSeaLevel, uTideHeight, uTime);
    vRel = vec3(in_xz.x * uExtent, level - uCameraPos.y, in_xz.y * uExtent);
    gl_Position = uViewProjRel * vec4(vRel, 1.0);
    vWorldPos = vec4(uCameraPos + vRel, FogVertexFactor(gl_Position));
}
