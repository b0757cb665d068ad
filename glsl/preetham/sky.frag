#version 330 core
// Preetham analytic sky seen by the camera (spec/001 §1.8). The model is in preetham.glsl.
#include "camera.glsl"
#include "preetham.glsl"

in vec2 vUV;
out vec4 fragColor;

void main() {
    fragColor = vec4(PreethamSkyRadiance(CameraRayDirection(vUV)), 1.0);
}
