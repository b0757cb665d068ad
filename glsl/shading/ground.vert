#version 330 core
// The shading lab's ground (spec/003 §2.1 lighting, spec/003 §2.8 shadows): a square at y = 0
// under the test objects, its vertices given in world space (no model matrix); the shading and
// the program's interface are documented in ground.frag.
// Failure cases guarded: none beyond the transform (the quad is built by the effect, finite).
in vec3 in_position;

uniform mat4 uViewProj;

out vec3 vWorldPos;

void main() {
    vWorldPos = in_position;
    gl_Position = uViewProj * vec4(in_position, 1.0);
}
