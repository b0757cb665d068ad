#version 330 core
// The surfaces lab's opaque surface (spec/003 §2.5–2.8): the vertex stage. The meshes are in
// world space already (app.sim.surfaces_scene.mesh), so no model matrix; the fragment stage,
// surface.frag, documents the program's interface and equations.
// Failure cases guarded: none beyond the fragment stage's (the normal and tangent are passed
// unnormalised and renormalised there).

in vec3 in_position;
in vec3 in_normal;
in vec2 in_uv;
in vec4 in_tangent;

uniform mat4 uViewProj;
uniform mat4 uView;

out vec3 vWorldPos;
out vec3 vWorldNormal;
out vec4 vWorldTangent;
out vec2 vUV;
out float vViewDepth;   // distance along the camera's view axis (the cascades' split variable)

void main() {
    vWorldPos = in_position;
    vWorldNormal = in_normal;
    vWorldTangent = in_tangent;
    vUV = in_uv;
    vViewDepth = -(uView * vec4(in_position, 1.0)).z;
    gl_Position = uViewProj * vec4(in_position, 1.0);
}
