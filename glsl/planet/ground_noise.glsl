// =============================================================================================
// The analytic Earth's land/sea noise (spec/002 §5: the test scene's Earth mesh, "Tierra",
// here a sphere): 5 octaves of Perlin's gradient noise (Perlin 2002; common/noise_perlin.glsl, twin
// app/sim/noise/gradient.py) over the unit sphere of directions from the Earth's centre,
//   f(n) = Σ_{i<5} 0.5^(i+1) · Perlin(q_i),   q_0 = 40 n + (1.7, 9.2, 3.3),  q_{i+1} = 2.03 q_i
// It depends on the direction alone, so it is baked once into a cubemap (ground_noise_bake.frag,
// rebuilt only when its size changes) and looked up by the scattering pass; the live sum stays
// selectable (planet.ground_noise = live) as the reference the bake is measured against.
// Failure cases guarded: the lattice coordinates stay below 40 · 2.03⁴ ≈ 680, far inside the
// noise's exact float range (2^16, see noise_perlin.glsl); n is normalised by the caller.
// =============================================================================================
#include "noise_perlin.glsl"

float GroundNoiseFbm(vec3 n) {
    float f = 0.0, amp = 0.5;
    vec3 q = n * 40.0 + vec3(1.7, 9.2, 3.3);
    for (int i = 0; i < 5; ++i) { f += amp * PerlinNoise3(q); q *= 2.03; amp *= 0.5; }
    return f;
}
