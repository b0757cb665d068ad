#version 330 core
// Test probe for the stereo pair (tests/gl/test_vr_stereo.py, spec/003 §2.15): the boxes'
// flat colours. No equation. Failure cases: none of its own.
in vec3 vColour;
out vec4 fragColor;

void main() {
    fragColor = vec4(vColour, 1.0);
}
