// The noise switch of the materials scene: the same material with the procedural-wood
// thesis's value noise (spec/004 §1.5–1.6) or Perlin's 2002 gradient noise.
#include "noise_value.glsl"
#include "noise_fbm.glsl"

uniform int uNoiseKind;   // 0 the thesis's value noise, 1 Perlin's gradient noise

// Three noise channels in [0, 1]: the wood's distortion source.
vec3 MaterialNoise3(vec3 p, int depth) {
    if (uNoiseKind == 0) return ThesisOctaves(p, depth);
    // Perlin fBm with the thesis's octave weights (lacunarity 2, gain ½, normalised), one
    // decorrelated lattice offset per channel, mapped from about [−1, 1] to [0, 1].
    int d = clamp(depth, 1, 8);
    vec3 fbm = vec3(PerlinFbm3(p, d, 2.0, 0.5),
                    PerlinFbm3(p + vec3(31.416, 47.853, 12.793), d, 2.0, 0.5),
                    PerlinFbm3(p + vec3(-73.156, 19.271, 61.932), d, 2.0, 0.5));
    return clamp(0.5 + 0.5 * fbm, 0.0, 1.0);
}

float MaterialNoise1(vec3 p) {
    if (uNoiseKind == 0) return ThesisNoise3(p).x * 2.0 - 1.0;
    return PerlinNoise3(p);
}
