#version 330 core
// One cubemap face of the sky, for contexts without compute shaders (macOS GL 4.1).
// Rows are written top-down as stored in the cubemap, matching sky_cubemap.comp.
#include "cubemap.glsl"
#include "sky_radiance.glsl"

in vec2 vUV;
out vec4 fragColor;
uniform int uFace;

void main() {
    vec2 st = vec2(vUV.x, vUV.y) * 2.0 - 1.0;
    fragColor = vec4(SkyRadiance(CubemapFaceDirection(uFace, st)), 1.0);
}
