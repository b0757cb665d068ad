#version 330 core
// The village's depth pre-pass (spec/003 §1), the fragment stage of ProgramSpec("village/depth"):
// nothing but the depth the rasteriser writes. Failure cases guarded: no colour is written (the
// colour mask is off while it draws), so a stray value can never reach the image.
out vec4 fragColor;

void main() {
    fragColor = vec4(0.0);
}
