// Fractal sums of noise: fBm, turbulence, inverted-Worley fBm and Perlin-Worley, each with a
// tileable variant for bakes.
//
// Sources: fBm, spec/001 §1.1, spec/001 eq. 3.1 and spec/001 eq. 3.2 (after Quilez);
// turbulence, Perlin 1985 (sum of |noise|); Perlin-Worley, Schneider, "The real-time
// volumetric cloudscapes of Horizon: Zero Dawn", SIGGRAPH 2015 (spec/001 §1.1:
// remap(perlin, worley - 1, 1, 0, 1), the shape texture's red channel). The maritime thesis's
// weather map is a Perlin fBm (spec/000 §1.6, GradientSimulator). Numpy twin:
// app/sim/noise/fractal.py.
// Needs noise_perlin.glsl and noise_worley.glsl (included here).
//
// Octave sums
// -----------
// With amplitudes a_0 = 1, a_i = G a_{i-1} (gain G) and frequencies f_0 = 1, f_i = L f_{i-1}
// (lacunarity L); for a Hurst exponent H, G = L^-H (spec/001 eq. 3.1 has L = 2, G = 2^-H,
// "usually 1/2"; the Python side converts H):
//
//     Fbm(p)        = sum_{i<n} a_i noise(f_i p)               / sum_{i<n} a_i
//                                                            (normalised spec/001 eq. 3.2)
//     Turbulence(p) = sum_{i<n} a_i |noise(f_i p)|             / sum_{i<n} a_i
//     WorleyFbm(p)  = sum_{i<n} a_i (1 - clamp(F1(f_i p),0,1)) / sum_{i<n} a_i  in [0, 1]
//
// The division by sum a_i (spec/001 eq. 3.2 is the bare sum) keeps each sum in its base
// noise's range: one octave is exactly the base noise (spec/001 B5), and Perlin-Worley gets
// known ranges.
//
// Perlin-Worley (the exact formula, also in app.sim.noise.fractal.perlin_worley_remap):
//
//     P  = clamp(0.5 + 0.5 PerlinFbm(p), 0, 1),   W = WorleyFbm(p)
//     PW = clamp(remap(P, W - 1, 1, 0, 1), 0, 1) = clamp((P + 1 - W) / (2 - W), 0, 1)
//
// with remap(v, l0, h0, l1, h1) = l1 + (v - l0)(h1 - l1)/(h0 - l0). W = 1 leaves P; W = 0
// gives (P + 1)/2: Worley billows lift the Perlin field. 2 - W >= 1: no division by zero.
//
// Tileable variants: octave i uses the periodic noise with period base_period * L^i, which
// needs an integer L; the whole sum then repeats with base_period in p on every axis.
//
// Failure cases guarded
// ---------------------
// * octaves outside [1, FBM_MAX_OCTAVES] are clamped (0 octaves would divide by zero; beyond
//   16 octaves of L = 2 float32 cannot resolve the detail anyway).
// * High octaves multiply p: keep |p f_{n-1}| below ~2^16 (see noise_perlin.glsl).
// * Integer lacunarity puts every octave's lattice through the integer points, where Perlin
//   noise is 0 — so PerlinFbm is 0 at integer p (a property of spec/001 eq. 3.1, kept for
//   fidelity).
// * The Perlin permutation texture (uPerlinPermutation) selects the Perlin seed; Worley sums
//   take the uint seed argument; all octaves share them.

#include "noise_perlin.glsl"
#include "noise_worley.glsl"

#ifndef FBM_MAX_OCTAVES
#define FBM_MAX_OCTAVES 16
#endif

int FbmOctaves(int octaves) { return clamp(octaves, 1, FBM_MAX_OCTAVES); }

// ---- Perlin fBm (spec/001 eq. 3.2, normalised) and turbulence ------------------------------

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

// Tileable: repeats with `period` (lattice units of octave 0) on every axis.
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

float PerlinTurbulence3Periodic(vec3 p, ivec3 period, int octaves, int lacunarity, float gain) {
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

float PerlinTurbulence2Periodic(vec2 p, ivec2 period, int octaves, int lacunarity, float gain) {
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

// Tileable: octave i has period * lacunarity^i cells per period of p.
float WorleyFbm3Periodic(vec3 p, ivec3 period, int octaves, int lacunarity, float gain, uint seed) {
    float sum = 0.0, norm = 0.0, amplitude = 1.0, frequency = 1.0;
    ivec3 octavePeriod = period;
    for (int i = 0; i < FbmOctaves(octaves); ++i) {
        sum += amplitude * WorleyInvertedF1(WorleyNoise3Periodic(p * frequency, octavePeriod, seed));
        norm += amplitude;
        amplitude *= gain;
        frequency *= float(lacunarity);
        octavePeriod *= lacunarity;
    }
    return sum / norm;
}

float WorleyFbm2Periodic(vec2 p, ivec2 period, int octaves, int lacunarity, float gain, uint seed) {
    float sum = 0.0, norm = 0.0, amplitude = 1.0, frequency = 1.0;
    ivec2 octavePeriod = period;
    for (int i = 0; i < FbmOctaves(octaves); ++i) {
        sum += amplitude * WorleyInvertedF1(WorleyNoise2Periodic(p * frequency, octavePeriod, seed));
        norm += amplitude;
        amplitude *= gain;
        frequency *= float(lacunarity);
        octavePeriod *= lacunarity;
    }
    return sum / norm;
}

// ---- Perlin-Worley -------------------------------------------------------------------------

// PW = clamp((P + 1 - W) / (2 - W), 0, 1), P = clamp(0.5 + 0.5 perlinFbm, 0, 1), W = worleyFbm.
float PerlinWorleyRemap(float perlinFbm, float worleyFbm) {
    float perlin01 = clamp(0.5 + 0.5 * perlinFbm, 0.0, 1.0);
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

float PerlinWorley3Periodic(vec3 p, ivec3 period, int octaves, int lacunarity, float gain, uint seed) {
    return PerlinWorleyRemap(PerlinFbm3Periodic(p, period, octaves, lacunarity, gain),
                             WorleyFbm3Periodic(p, period, octaves, lacunarity, gain, seed));
}

float PerlinWorley2Periodic(vec2 p, ivec2 period, int octaves, int lacunarity, float gain, uint seed) {
    return PerlinWorleyRemap(PerlinFbm2Periodic(p, period, octaves, lacunarity, gain),
                             WorleyFbm2Periodic(p, period, octaves, lacunarity, gain, seed));
}
