// Fractal sums of noise: fBm, turbulence, inverted-Worley fBm and Perlin–Worley, each with a
// tileable variant for bakes. fBm: spec/001 §1.1, after Quilez; turbulence: Perlin 1985 (a sum
// of |noise|); Perlin–Worley: Schneider 2015, the clouds of Horizon: Zero Dawn (spec/001 §1.1,
// the shape texture's red channel). The maritime thesis's weather map is a Perlin fBm (spec/000
// §1.6, GradientSimulator). Numpy twin: app/sim/noise/fractal.py. Needs noise_perlin.glsl and
// noise_worley.glsl (included here). The Perlin permutation texture (uPerlinPermutation) selects
// the Perlin seed, the Worley sums take the uint seed argument; all octaves share them.
// Failure cases guarded: an octave count outside [1, FBM_MAX_OCTAVES] (FbmOctaves). Left to the
// caller: high octaves multiply p, so keep |p · fₙ₋₁| below ~2¹⁶ (see noise_perlin.glsl);
// integer lacunarity puts every octave's lattice through the integer points, where Perlin noise
// is 0, so PerlinFbm is 0 at integer p (a property of spec/001 eq. 3.1, kept for fidelity).

#include "noise_perlin.glsl"
#include "noise_worley.glsl"

#ifndef FBM_MAX_OCTAVES
#define FBM_MAX_OCTAVES 16
#endif

// The octave count used. Failure case: outside [1, FBM_MAX_OCTAVES] it is clamped (0 octaves
// would divide by zero; beyond 16 octaves of L = 2 float32 cannot resolve the detail anyway).
int FbmOctaves(int octaves) { return clamp(octaves, 1, FBM_MAX_OCTAVES); }

// ---- Perlin fBm (spec/001 eq. 3.2, normalised) and turbulence ------------------------------
// Every sum here has amplitudes a₀ = 1, aᵢ = G·aᵢ₋₁ (gain G) and frequencies f₀ = 1,
// fᵢ = L·fᵢ₋₁ (lacunarity L); for a Hurst exponent H, G = L⁻ᴴ (spec/001 eq. 3.1 has L = 2,
// G = 2⁻ᴴ, "usually 1/2"; the Python side converts H). Each is divided by Σ aᵢ, which
// spec/001 eq. 3.2's bare sum is not: that keeps a sum in its base noise's range (one octave is
// exactly the base noise, spec/001 §1.1 criterion B5, and Perlin–Worley gets known ranges).
// Tileable variants: octave i uses the periodic noise with period base_period · L^i, which needs
// an integer L; the whole sum then repeats with base_period in p on every axis.

// Fbm(p) = Σᵢ aᵢ·noise(fᵢ·p) / Σᵢ aᵢ over the n octaves: spec/001 eq. 3.1 and spec/001 eq. 3.2,
// normalised, of Perlin noise; p in lattice units, the result in the noise's range.
float PerlinFbm3(vec3 p, int octaves, float lacunarity, float gain) {
    float sum = 0.0, norm = 0.0, amplitude = 1.0, frequency = 1.0;
    for (int i = 0; i < FbmOctaves(octaves); ++i) {
        sum += amplitude * PerlinNoise3(p * frequency);
        norm += amplitude;
        amplitude *= gain;
        frequency *= lacunarity;
    }
    return sum / norm;
}

float PerlinFbm2(vec2 p, int octaves, float lacunarity, float gain) {
    float sum = 0.0, norm = 0.0, amplitude = 1.0, frequency = 1.0;
    for (int i = 0; i < FbmOctaves(octaves); ++i) {
        sum += amplitude * PerlinNoise2(p * frequency);
        norm += amplitude;
        amplitude *= gain;
        frequency *= lacunarity;
    }
    return sum / norm;
}

// Turbulence(p) = Σᵢ aᵢ·|noise(fᵢ·p)| / Σᵢ aᵢ over the n octaves (Perlin 1985), in [0, ~1.04].
float PerlinTurbulence3(vec3 p, int octaves, float lacunarity, float gain) {
    float sum = 0.0, norm = 0.0, amplitude = 1.0, frequency = 1.0;
    for (int i = 0; i < FbmOctaves(octaves); ++i) {
        sum += amplitude * abs(PerlinNoise3(p * frequency));
        norm += amplitude;
        amplitude *= gain;
        frequency *= lacunarity;
    }
    return sum / norm;
}

float PerlinTurbulence2(vec2 p, int octaves, float lacunarity, float gain) {
    float sum = 0.0, norm = 0.0, amplitude = 1.0, frequency = 1.0;
    for (int i = 0; i < FbmOctaves(octaves); ++i) {
        sum += amplitude * abs(PerlinNoise2(p * frequency));
        norm += amplitude;
        amplitude *= gain;
        frequency *= lacunarity;
    }
    return sum / norm;
}

// The tileable sums: they repeat with `period` (lattice units of octave 0) on every axis.
float PerlinFbm3Periodic(vec3 p, ivec3 period, int octaves, int lacunarity, float gain) {
    float sum = 0.0, norm = 0.0, amplitude = 1.0, frequency = 1.0;
    ivec3 octavePeriod = period;
    for (int i = 0; i < FbmOctaves(octaves); ++i) {
        sum += amplitude * PerlinNoise3Periodic(p * frequency, octavePeriod);
        norm += amplitude;
        amplitude *= gain;
        frequency *= float(lacunarity);
        octavePeriod *= lacunarity;
    }
    return sum / norm;
}

float PerlinFbm2Periodic(vec2 p, ivec2 period, int octaves, int lacunarity, float gain) {
    float sum = 0.0, norm = 0.0, amplitude = 1.0, frequency = 1.0;
    ivec2 octavePeriod = period;
    for (int i = 0; i < FbmOctaves(octaves); ++i) {
        sum += amplitude * PerlinNoise2Periodic(p * frequency, octavePeriod);
        norm += amplitude;
        amplitude *= gain;
        frequency *= float(lacunarity);
        octavePeriod *= lacunarity;
    }
    return sum / norm;
}

float PerlinTurbulence3Periodic(vec3 p, ivec3 period, int octaves, int lacunarity,
                                float gain) {
    float sum = 0.0, norm = 0.0, amplitude = 1.0, frequency = 1.0;
    ivec3 octavePeriod = period;
    for (int i = 0; i < FbmOctaves(octaves); ++i) {
        sum += amplitude * abs(PerlinNoise3Periodic(p * frequency, octavePeriod));
        norm += amplitude;
        amplitude *= gain;
        frequency *= float(lacunarity);
        octavePeriod *= lacunarity;
    }
    return sum / norm;
}

float PerlinTurbulence2Periodic(vec2 p, ivec2 period, int octaves, int lacunarity,
                                float gain) {
    float sum = 0.0, norm = 0.0, amplitude = 1.0, frequency = 1.0;
    ivec2 octavePeriod = period;
    for (int i = 0; i < FbmOctaves(octaves); ++i) {
        sum += amplitude * abs(PerlinNoise2Periodic(p * frequency, octavePeriod));
        norm += amplitude;
        amplitude *= gain;
        frequency *= float(lacunarity);
        octavePeriod *= lacunarity;
    }
    return sum / norm;
}

// ---- inverted-Worley fBm (spec/001 eq. 3.2 over the inverted F1, normalised) ---------------

// WorleyFbm(p) = Σᵢ aᵢ·(1 − clamp(F1(fᵢ·p), 0, 1)) / Σᵢ aᵢ over the n octaves, in [0, 1]; p in cell
// units.
float WorleyFbm3(vec3 p, int octaves, float lacunarity, float gain, uint seed) {
    float sum = 0.0, norm = 0.0, amplitude = 1.0, frequency = 1.0;
    for (int i = 0; i < FbmOctaves(octaves); ++i) {
        sum += amplitude * WorleyInvertedF1(WorleyNoise3(p * frequency, seed));
        norm += amplitude;
        amplitude *= gain;
        frequency *= lacunarity;
    }
    return sum / norm;
}

float WorleyFbm2(vec2 p, int octaves, float lacunarity, float gain, uint seed) {
    float sum = 0.0, norm = 0.0, amplitude = 1.0, frequency = 1.0;
    for (int i = 0; i < FbmOctaves(octaves); ++i) {
        sum += amplitude * WorleyInvertedF1(WorleyNoise2(p * frequency, seed));
        norm += amplitude;
        amplitude *= gain;
        frequency *= lacunarity;
    }
    return sum / norm;
}

// Tileable: octave i has period · lacunarity^i cells per period of p.
float WorleyFbm3Periodic(vec3 p, ivec3 period, int octaves, int lacunarity, float gain,
                         uint seed) {
    float sum = 0.0, norm = 0.0, amplitude = 1.0, frequency = 1.0;
    ivec3 octavePeriod = period;
    for (int i = 0; i < FbmOctaves(octaves); ++i) {
        sum += amplitude
               * WorleyInvertedF1(WorleyNoise3Periodic(p * frequency, octavePeriod, seed));
        norm += amplitude;
        amplitude *= gain;
        frequency *= float(lacunarity);
        octavePeriod *= lacunarity;
    }
    return sum / norm;
}

float WorleyFbm2Periodic(vec2 p, ivec2 period, int octaves, int lacunarity, float gain,
                         uint seed) {
    float sum = 0.0, norm = 0.0, amplitude = 1.0, frequency = 1.0;
    ivec2 octavePeriod = period;
    for (int i = 0; i < FbmOctaves(octaves); ++i) {
        sum += amplitude
               * WorleyInvertedF1(WorleyNoise2Periodic(p * frequency, octavePeriod, seed));
        norm += amplitude;
        amplitude *= gain;
        frequency *= float(lacunarity);
        octavePeriod *= lacunarity;
    }
    return sum / norm;
}

// ---- Perlin–Worley -------------------------------------------------------------------------

const float FBM_SIGNED_TO_UNIT = 0.5;  // [−1, 1] onto [0, 1]: 0.5 + 0.5 v

// Perlin–Worley from the two sums, in [0, 1] (Schneider 2015; the exact formula is also
// app.sim.noise.fractal.perlin_worley_remap): with P = clamp(0.5 + 0.5 perlinFbm, 0, 1) and
// W = worleyFbm, PW = clamp(remap(P, W − 1, 1, 0, 1), 0, 1) = clamp((P + 1 − W)/(2 − W), 0, 1),
// remap(v, l0, h0, l1, h1) = l1 + (v − l0)(h1 − l1)/(h0 − l0). W = 1 leaves P; W = 0 gives
// (P + 1)/2: the Worley billows lift the Perlin field. 2 − W ≥ 1: no division by zero.
float PerlinWorleyRemap(float perlinFbm, float worleyFbm) {
    float perlin01 = clamp(FBM_SIGNED_TO_UNIT + FBM_SIGNED_TO_UNIT * perlinFbm, 0.0, 1.0);
    return clamp((perlin01 + 1.0 - worleyFbm) / (2.0 - worleyFbm), 0.0, 1.0);
}

// Perlin fBm and inverted-Worley fBm with the same octave parameters, combined.
float PerlinWorley3(vec3 p, int octaves, float lacunarity, float gain, uint seed) {
    return PerlinWorleyRemap(PerlinFbm3(p, octaves, lacunarity, gain),
                             WorleyFbm3(p, octaves, lacunarity, gain, seed));
}

float PerlinWorley2(vec2 p, int octaves, float lacunarity, float gain, uint seed) {
    return PerlinWorleyRemap(PerlinFbm2(p, octaves, lacunarity, gain),
                             WorleyFbm2(p, octaves, lacunarity, gain, seed));
}

float PerlinWorley3Periodic(vec3 p, ivec3 period, int octaves, int lacunarity, float gain,
                            uint seed) {
    return PerlinWorleyRemap(PerlinFbm3Periodic(p, period, octaves, lacunarity, gain),
                             WorleyFbm3Periodic(p, period, octaves, lacunarity, gain, seed));
}

float PerlinWorley2Periodic(vec2 p, ivec2 period, int octaves, int lacunarity, float gain,
                            uint seed) {
    return PerlinWorleyRemap(PerlinFbm2Periodic(p, period, octaves, lacunarity, gain),
                             WorleyFbm2Periodic(p, period, octaves, lacunarity, gain, seed));
}
