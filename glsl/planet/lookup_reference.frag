#version 330 core
// =============================================================================================
// The planet bench's yardstick for method 4's per-pixel pass (beyond the thesis: Hillaire 2020
// §5 sets the goal that the sky costs a few lookups per pixel): one trilinear read of a 3D
// texture per pixel — what a precomputed-scattering sky lookup (Bruneton 2017) costs — so that
// `natura bench planet` can state the scattering pass as a multiple of it in the same rounds.
// The read position varies across the image (x, y and depth), so every pixel filters eight
// texels as a real lookup does; the result is written, so the read cannot be optimised away.
// Failure cases: none (coordinates stay inside [0, 1]; the volume clamps at its edges).
// =============================================================================================
in vec2 vUV;
out vec4 fragColor;

uniform sampler3D uVolume;   // RGBA32F, LINEAR, CLAMP_TO_EDGE (the aerial-perspective format)

void main() {
    fragColor = texture(uVolume, vec3(vUV, 0.25 + 0.5 * vUV.x * vUV.y));
}
