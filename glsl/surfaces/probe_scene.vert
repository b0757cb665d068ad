#version 330 core
// The surfaces lab's probe test scene (spec/003 §2.5): world-space meshes of
// app.sim.surfaces_scene drawn with their world position as colour, so a probe's cubemap
// tells where each texel's ray hit (tests/gl/test_surfaces_reflections.py and
// app/bench/surfaces_reflections.py compare it with the exact ray cast).
// Failure cases guarded: none beyond the fragment shader's (positions pass through).
in vec3 in_position;
uniform mat4 uViewProj;
out vec3 vWorld;

void main() {
    vWorld = in_position;
    gl_Position = uViewProj * vec4(in_position, 1.0);
}
