#version 330 core
// Procedural solid materials (spec/004 §1.6): the vertex shader hands the untransformed
// object-space position to the fragment shader, so the texture is anchored to the object.
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
