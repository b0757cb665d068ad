#version 330 core
// The ground fog plane (spec/003 §2.11 a, Custom/Fog), program ProgramSpec("fog/plane"): this
// file + plane.frag. A flat grid just above the island's ground (app/effects/fog/plane.py puts
// it at the land's median height plus fog.plane_height and spans the land); the vertex shader
// scrolls the texture's uv with the wind — the thesis's uv.y += _Speed·_Time.x (_Time.x = t/20),
// integrated per frame by the effect along the wind's direction (uScroll) — and computes the
// global fog's factor of the vertex like every lit surface (fog.glsl: spec/003 eq. 7.24,
// spec/003 eq. 7.27, spec/003 eq. 7.28, spec/003 eq. 7.29), carried in the w of the world
// position.
// Failure cases guarded: the uv from world xz (not from a mesh's 0–1 uv), so the texture's
// density in metres does not depend on how large the island's plane is; the scroll is an offset
// accumulated on the CPU, so a changed Speed or wind never makes the texture jump; the tile
// size kept above zero.
#include "fog.glsl"

in vec2 in_position;        // world (x, z) of the vertex [m]

uniform mat4 uViewProj;
uniform float uPlaneY;      // the plane's height [m]
uniform vec2 uScroll;       // the uv offset [tiles]
uniform float uPlaneTile; // @param 24 [2, 200] step=0.5 unit=m §2.11 metres of ground one tile of
                          // the fog texture covers
uniform vec4 uMaskRect;     // (x0, z0, 1/width, 1/depth) of the ground mask [m, 1/m]

out vec4 vWorldPos;         // xyz world position, w the global fog's factor of this vertex
out vec2 vUV;
out vec2 vMaskUV;

void main() {
    vec3 p = vec3(in_position.x, uPlaneY, in_position.y);
    gl_Position = uViewProj * vec4(p, 1.0);
    vWorldPos = vec4(p, FogVertexFactor(gl_Position));
    vUV = p.xz / max(uPlaneTile, 1e-3) + uScroll;
    vMaskUV = (p.xz - uMaskRect.xy) * uMaskRect.zw;
}
