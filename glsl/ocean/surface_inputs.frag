#version 330 core
// Deferred ocean, pass 1 of the mesh (spec/000 §1.1–1.2): the surface mesh (surface.vert, the
// displacement of spec/000 eq. 2.5 and spec/000 eq. 2.11) writes only its shading inputs — the
// camera-relative point, the wave height, the rest point and the pixel's footprint — so the
// expensive shading (normals of spec/000 eq. 2.2, spec/000 eq. 2.4 and the FFT slopes, Fresnel,
// glitter, foam; shade.frag) runs once per covered pixel instead of once per pixel of every 4×4
// block a tiny far triangle touches (software rasterisers shade whole blocks).
// Targets: 0 = (p − camera, η), 1 = (rest point − camera.xz, footprint m, kind = 1: mesh),
// 2 = (d off / dx, d off / dy): the screen derivatives that mip-filter the FFT's textures.
// Failure cases guarded: the footprint comes from fwidth here, where the triangle's derivatives
// exist (the full-screen shading pass has none), with the forward pass's floor of 1e-4 m; float
// targets (RGBA32F) keep metres exact at the mesh's extent; depth is tested and written against
// the scene's depth exactly as the forward pass does, so the same fragments win; fragments
// inside a floating object's dry volume (dry_mask.glsl) are discarded as in the forward pass.
in vec2 vOff;
in vec3 vRel;
in float vHeight;

layout(location = 0) out vec4 gRel;
layout(location = 1) out vec4 gSurf;
layout(location = 2) out vec4 gGrad;

#ifdef OCEAN_FLOATING  // a scene with floating objects: their dry volumes
#include "dry_mask.glsl"
#endif

void main() {
#ifdef OCEAN_FLOATING
    if (InsideDryVolume()) discard;  // inside a hull: no input, so no water shaded there
#endif
    float footprint = max(length(fwidth(vOff)), 1e-4);
    gRel = vec4(vRel, vHeight);
    gSurf = vec4(vOff, footprint, 1.0);
    gGrad = vec4(dFdx(vOff), dFdy(vOff));
}
