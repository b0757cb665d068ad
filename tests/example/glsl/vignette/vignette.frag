#version 330 core
// Natural vignetting of a camera lens (beyond the theses: the example effect of
// docs/architecture.md): the irradiance at the image plane falls off as cos⁴ θ of the angle
// between a pixel's ray and the optical axis (the cosine-fourth law of radiometry).
//   factor = mix(1, cos⁴ θ, uAmount)      image = image · factor (multiplicative blending)
// Failure cases guarded: rays past 90° of the axis cannot occur in a perspective view, and
// cos θ is clamped to [0, 1] before the power.
#include "camera.glsl"

in vec2 vUV;
out vec4 fragColor;

uniform float uAmount;  // @param 1 [0, 1] step=0.01 how much of the cos⁴ falloff to apply (0: none)

void main() {
    float cosTheta = clamp(dot(CameraRayDirection(vUV), uCamForward), 0.0, 1.0);
    float c2 = cosTheta * cosTheta;
    fragColor = vec4(vec3(mix(1.0, c2 * c2, uAmount)), 1.0);
}
