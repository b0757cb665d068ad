#version 330 core
// Depth only: the faces of the boat's dry volume (spec/000 §4 item 8; dry_depth.vert).
// Equations: none. Failure cases guarded: none beyond the vertex stage's (no colour is written).
void main() {
}
