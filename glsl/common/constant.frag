#version 330 core
// The cheapest full-screen pass: the bench's reference for ratios.
out vec4 fragColor;
uniform vec4 uColor;
void main() { fragColor = uColor; }
