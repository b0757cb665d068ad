#version 330 core
// Depth only: the depth attachment is all this pass writes — the fragment stage of the
// shadow-map pipeline from the sun (spec/002 §3.1; shadow_depth.vert has the transform).
// Equations: none (the thesis's fragment shader "outputs Z depth").
// Failure cases: none beyond the pass's (no colour output, so nothing to clamp); acne and
// out-of-map points are handled where the map is read (shadow.glsl).
void main() {}
