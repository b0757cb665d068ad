#version 330 core
// Test probe for the stereo pair (tests/gl/test_vr_stereo.py, spec/003 §2.15): boxes of flat
// colours seen through one camera's view-projection, so each eye of app.render.stereo can be
// compared with a mono render from that eye's camera. No equation.
// Failure cases: none of its own (positions camera-relative, as every pass of the app).
in vec3 in_position;
in vec3 in_colour;
uniform mat4 uViewProj;   // for camera-relative positions
uniform vec3 uCameraPos;
out vec3 vColour;

void main() {
    vColour = in_colour;
    gl_Position = uViewProj * vec4(in_position - uCameraPos, 1.0);
}
