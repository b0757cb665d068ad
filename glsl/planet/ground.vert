#version 330 core
// The planet's ground pass (planet/ground.frag, spec/002 §5): one triangle covering the screen
// on the far plane, drawn after the meshes into the G-buffer with the depth test '<=' and no
// depth writes, so only the pixels no mesh covers are shaded.
// Equations: none (z = w puts every vertex at window depth 1, the G-buffer's clear value).
// Failure cases: z = w is inside the clip volume (−w ≤ z ≤ w), so the triangle is not clipped
// away at the far plane; vUV is (0,0) bottom-left to (1,1) top-right as common/fullscreen.vert.
out vec2 vUV;

void main() {
    vec2 p = vec2((gl_VertexID << 1) & 2, gl_VertexID & 2);
    vUV = p;
    gl_Position = vec4(p * 2.0 - 1.0, 1.0, 1.0);
}
