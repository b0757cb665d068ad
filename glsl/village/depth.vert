#version 330 core
// The village's depth pre-pass (spec/003 §1: the opaque queue drawn front to back, here made
// exact), program ProgramSpec("village/depth"): this file + depth.frag. Every opaque batch's
// depth is written first with no shading at all; surface.vert then draws the same vertices with
// a depth test of less-or-equal, so the lit, parallax-mapped and shadowed surface.frag runs once
// per visible pixel instead of once per covering triangle (the island's hills hide one another,
// and the houses stand in front of the ground).
// Failure cases guarded: the position is the same expression of the same inputs as
// surface.vert's and both are declared invariant, so the two passes write bit-equal depths
// (no speckles of the ground failing its own depth test); the batches' other attributes are
// skipped by the vertex array (one position per 68-byte vertex).
invariant gl_Position;

in vec3 in_position;

uniform mat4 uViewProj;

void main() {
    gl_Position = uViewProj * vec4(in_position, 1.0);
}
