#version 330 core
// Meshes of the planet scene (mountains, city block) in the local tangent frame at the scene
// origin; positions are made camera-relative here (spec/002 §2.1: `obj` = world-space position,
// here relative to the camera so float32 holds up from the ground to space).
// Equations: none (the transform of spec/002 §2.1).
// Failure cases guarded: float32 precision at planet scale — the camera's local position
// comes from the CPU and positions are camera-relative before the rotation-only view ×
// projection; normals and tangents are passed unnormalised (the fragment stage normalises).
// gl_Position is invariant: the depth pre-pass (planet/shadow_depth.frag on this vertex stage)
// and the shading pass must produce the same depths for the shading pass's test '<='.
in vec3 in_position;
in vec3 in_normal;
in vec3 in_tangent;
in vec2 in_uv;

uniform vec3 uCameraLocal;  // camera position in the local frame (m)
uniform mat4 uViewProj;     // rotation-only view × projection

out vec3 vRel;
out vec3 vLocal;
out vec3 vNormal;
out vec3 vTangent;
out vec2 vUv;
invariant gl_Position;

void main() {
    vLocal = in_position;
    vRel = in_position - uCameraLocal;
    vNormal = in_normal;
    vTangent = in_tangent;
    vUv = in_uv;
    gl_Position = uViewProj * vec4(vRel, 1.0);
}
