#version 330 core
// The boat's dry volume (spec/000 §4 item 8): the hull closed by its deck raised by a bulwark,
// drawn depth-only twice — front faces nearest, back faces farthest — so the water can discard its
// fragments inside the boat (glsl/common/dry_mask.glsl).
// Equations: none (a rigid transform, the hull's own: hull.vert).
// Failure cases guarded: the same camera-relative transform as the hull and the ocean, so the
// depths compare exactly.
in vec3 in_position;

uniform mat4 uModelRel;
uniform mat4 uViewProjRel;

void main() {
    gl_Position = uViewProjRel * (uModelRel * vec4(in_position, 1.0));
}
