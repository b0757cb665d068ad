#version 330 core
// Deferred ocean, the far plane's inputs (spec/000 §1.1–1.2): as far.frag, each pixel's view
// ray meets the mean sea level y = 0 analytically beyond the mesh, but only the shading inputs
// are written (shade.frag shades them); drawn over the band of rows between the horizon and the
// mesh's end (band.vert; app/effects/ocean/deferred.py), not the whole screen.
// Targets: 0 = (p − camera, 0), 1 = (p.xz − camera.xz, footprint m, kind = 2: far plane),
// 2 = (d p.xz / dx, d p.xz / dy): the screen derivatives that mip-filter the FFT's textures.
// Equations: t = y_cam / −dir.y; footprint = t · (2·tan(fov/2)/H) / −dir.y (the pixel stretched
// by the grazing angle).
// Failure cases guarded: rays at or above the horizon are discarded (no division by dir.y ≈ 0
// → inf/NaN); pixels nearer than the mesh's extent are left to the mesh; depth is clamped just
// inside the far plane, so later passes (fog, clouds) see the sea and the shading pass's
// depth test (GREATER than the cleared 1) keeps it.
in vec2 vUV;

uniform mat4 uViewProjRel;
uniform float uFarStart;     // m: the mesh covers the sea nearer than this
uniform vec2 uViewport;

layout(location = 0) out vec4 gRel;
layout(location = 1) out vec4 gSurf;
layout(location = 2) out vec4 gGrad;

#include "camera.glsl"

void main() {
    vec3 dir = CameraRayDirection(vUV);
    if (dir.y > -1e-6 || uCameraPos.y <= 0.0) discard;
    float t = uCameraPos.y / -dir.y;
    vec3 rel = dir * t;
    if (length(rel.xz) < uFarStart) discard;
    float pix = 2.0 * uTanHalfFov / uViewport.y;
    float footprint = t * pix / max(-dir.y, 1e-3);
    gRel = vec4(rel, 0.0);
    gSurf = vec4(rel.xz, footprint, 2.0);
    gGrad = vec4(dFdx(rel.xz), dFdy(rel.xz));
    vec4 clip = uViewProjRel * vec4(rel, 1.0);
    gl_FragDepth = min(clip.z / clip.w * 0.5 + 0.5, 0.99999);
}
