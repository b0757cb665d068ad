#version 330 core
// The village's lit surfaces (spec/003 §1, §2.12: the CelShader and ComplexCelShader objects and
// the parallax-mapped terrain), program ProgramSpec("village/surface"): this file +
// surface.frag. Vertices arrive in world space (app/sim/village_meshes.py: the island, the
// houses, the props, the lamps, the bonfire, the people placed on the CPU).
// Equations: the global fog's factor per vertex, carried in the w of the world position — the
// thesis's packing (spec/003 §2.11; in fog.glsl: spec/003 eq. 7.24, spec/003 eq. 7.27,
// spec/003 eq. 7.28, spec/003 eq. 7.29).
// Failure cases guarded: normals and tangents passed as they are and re-normalised per fragment
// (interpolation shortens them); no model matrix, so no non-uniform scale to mistreat.
#include "fog.glsl"

invariant gl_Position;

in vec3 in_position;
in vec3 in_normal;
in vec2 in_uv;
in vec4 in_tangent;
in vec3 in_colour;
in vec2 in_mask;

uniform mat4 uViewProj;

out vec4 vWorldPos;       // xyz world position, w the fog factor of this vertex
out vec3 vWorldNormal;
out vec4 vWorldTangent;
out vec2 vUV;
out vec3 vColour;
out vec2 vMask;

void main() {
    gl_Position = uViewProj * vec4(in_position, 1.0);
    vWorldPos = vec4(in_position, FogVertexFactor(gl_Position));
    vWorldNormal = in_normal;
    vWorldTangent = in_tangent;
    vUV = in_uv;
    vColour = in_colour;
    vMask = in_mask;
}
