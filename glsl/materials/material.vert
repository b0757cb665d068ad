#version 330 core
// Procedural solid materials (spec/004 §1.6): the vertex shader hands the untransformed
// object-space position to the fragment shader, so the texture is anchored to the object.
// Equations: none (a solid texture is a function of the object-space point, spec/004 §1.1).
// Failure cases guarded: the texture swimming over a moving object (it reads the object-space
// position, never the world one); normals are transformed by mat3(uModel), which is exact
// only because uModel is limited to rotation, translation and uniform scale (a non-uniform
// scale would need the inverse transpose); the fragment shader renormalises them.
in vec3 in_position;
in vec3 in_normal;

uniform mat4 uModel;     // rotation, translation and uniform scale only
uniform mat4 uViewProj;

out vec3 vObjectPos;
out vec3 vWorldPos;
out vec3 vWorldNormal;

void main() {
    vObjectPos = in_position;
    vec4 world = uModel * vec4(in_position, 1.0);
    vWorldPos = world.xyz;
    vWorldNormal = mat3(uModel) * in_normal;
    gl_Position = uViewProj * world;
}
