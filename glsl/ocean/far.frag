#version 330 core
// The sea beyond the mesh, out to the horizon (spec/000 §1.1–1.2): each pixel's view ray meets
// the mean sea level y = 0 analytically; the waves there are too small on screen to displace, so
// only their normals (mip-filtered, footprint-filtered) and glitter are shaded. Writes its depth,
// clamped just inside the far plane, so later passes (fog, clouds) see the sea. The forward path
// (ocean.shading = forward) over the whole screen; the deferred path draws far_inputs.frag over
// the far plane's band of rows only.
// Guards: rays at or above the horizon are discarded (no division by dir.y ≈ 0 → inf/NaN);
// pixels nearer than the mesh's extent are left to the mesh.
in vec2 vUV;

uniform mat4 uViewProjRel;
uniform float uFarStart;     // m: the mesh covers the sea nearer than this
uniform vec2 uViewport;

out vec4 fragColor;

#include "camera.glsl"
#include "ocean/waves.glsl"
#include "ocean/shading.glsl"

void main() {
    vec3 dir = CameraRayDirection(vUV);
    if (dir.y > -1e-6 || uCameraPos.y <= 0.0) discard;
    float t = uCameraPos.y / -dir.y;
    vec3 rel = dir * t;
    if (length(rel.xz) < uFarStart) discard;
    // footprint: the pixel's size on the water, stretched by the grazing angle
    float pix = 2.0 * uTanHalfFov / uViewport.y;
    float footprint = t * pix / max(-dir.y, 1e-3);
    vec3 n;
    float foam, lost;
    OceanSurface(rel.xz, footprint, n, foam, lost);
    vec3 c = OceanShadeAbove(rel, n, -dir, foam, lost, 0.0);
    fragColor = vec4(max(c, vec3(0.0)), 1.0);
    vec4 clip = uViewProjRel * vec4(rel, 1.0);
    gl_FragDepth = min(clip.z / clip.w * 0.5 + 0.5, 0.99999);
}
