#version 330 core
// Copies one eye's image (linear radiance) into its half of a side-by-side stereo frame
// (spec/003 §2.15: each eye rendered on its own, into its own render texture, then shown side by
// side); app.render.stereo sets the viewport to the eye's half. No equation: a resampling copy.
// Failure cases guarded: an eye image of another size (render scale ≠ 1) is read with bilinear
// filtering at the half's pixel centres, never outside [0, 1] (clamped).
in vec2 vUV;
out vec4 fragColor;

uniform sampler2D uEye;

void main() {
    fragColor = vec4(texture(uEye, clamp(vUV, 0.0, 1.0)).rgb, 1.0);
}
