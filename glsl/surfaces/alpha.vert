#version 330 core
// The alpha quads of the surfaces lab (spec/003 §2.4 transparency): the vertex stage of
// ProgramSpec("surfaces/alpha"); the modes, the queues and the compositing are in alpha.frag.
// World-space vertices (no model matrix): in_position, in_normal, in_uv (in_tangent unused).
// vViewDepth is the clip w, the view-space depth −z of a perspective projection (the |z| of
// the depth weights of McGuire and Bavoil 2013).
// Failure cases guarded: a vertex at or behind the camera plane gives w ≤ 0, which the
// rasteriser clips; the fragment stage clamps |z| before using it.
in vec3 in_position;
in vec3 in_normal;
in vec2 in_uv;

uniform mat4 uViewProj;

out vec3 vWorldPos;
out vec3 vNormal;
out vec2 vUV;
out float vViewDepth;

void main() {
    vWorldPos = in_position;
    vNormal = in_normal;
    vUV = in_uv;
    gl_Position = uViewProj * vec4(in_position, 1.0);
    vViewDepth = gl_Position.w;
}
