#version 330 core
// Display pass: HDR scene radiance → tone-mapped, sRGB-encoded 8-bit window pixels.
#include "tonemap.glsl"

in vec2 vUV;
out vec4 fragColor;

uniform sampler2D uScene;
uniform float uExposure;
uniform int uTonemap;

void main() {
    vec3 radiance = texture(uScene, vUV).rgb;
    // NaN/Inf must not spread over the screen through filtering: show them as magenta.
    if (any(isnan(radiance)) || any(isinf(radiance))) { fragColor = vec4(1.0, 0.0, 1.0, 1.0); return; }
    fragColor = vec4(LinearToSrgb(Tonemap(radiance, uExposure, uTonemap)), 1.0);
}
