#version 330 core
// The surfaces lab's probe test scene (spec/003 §2.5): uColourMode 0 writes the fragment's
// world position as its colour (RGBA16F keeps ~2 mm at the room's 4 m), so a capture says
// where each texel's ray hit; 1 writes a plain radiance — uAlbedo × a 0.5 m checker
// (0.6 / 1.0), the ceiling (y above uCeiling) glowing 3× — for the metallic/dielectric bench.
// Failure cases guarded: none needed (no division, no texture); alpha is always 1.
in vec3 vWorld;
out vec4 fragColor;

uniform int uColourMode;
uniform vec3 uAlbedo;
uniform float uCeiling;

void main() {
    if (uColourMode == 0) {
        fragColor = vec4(vWorld, 1.0);
        return;
    }
    vec3 c = floor(vWorld * 2.0 + 1e-3);
    float checker = mod(c.x + c.y + c.z, 2.0) < 0.5 ? 0.6 : 1.0;
    float glow = vWorld.y > uCeiling ? 3.0 : 1.0;
    fragColor = vec4(uAlbedo * checker * glow, 1.0);
}
