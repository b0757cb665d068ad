#version 330 core
// The outline G-buffer (spec/003 §2.14), fragment stage: rgb the unit view-space normal (turned
// toward the camera on a back face), a the linear view depth (metres). The target is RGBA32F,
// cleared to (0, 0, 0, background depth) by app.effects.shading.outlines.
// Failure cases guarded: a zero interpolated normal (degenerate triangle) writes +z (facing the
// camera) instead of NaN; back faces (open meshes, the lab draws without culling) flip their
// normal so n·v stays ≥ 0.
in vec3 vViewNormal;
in float vViewDepth;

out vec4 fragColor;

void main() {
    float len = length(vViewNormal);
    vec3 n = len > 1e-8 ? vViewNormal / len : vec3(0.0, 0.0, 1.0);
    if (!gl_FrontFacing) n = -n;
    fragColor = vec4(n, vViewDepth);
}
