#version 330 core
// Day–night sky seen by the camera (spec/000 §1.7). The model is in sky_radiance.glsl.
#include "camera.glsl"
#include "sky_radiance.glsl"

in vec2 vUV;
out vec4 fragColor;

void main() {
    fragColor = vec4(SkyRadiance(CameraRayDirection(vUV)), 1.0);
}
