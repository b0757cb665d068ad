// =============================================================================================
// The grass's one wind and its per-blade randomness (spec/003 §2.9), for the vertex and
// geometry stages of glsl/grass/ (blades_gs.geom, billboard.vert, instanced.vert). Numpy twin:
// app/sim/grass.py (gs_phase, gs_omega, gs_amplitude, gs_wind, bb_sine, bb_wind_offset).
//
// (a) The geometry-shader blades (spec/003 §2.9 a), P the blade's centroid in object space
//     (the village's root triangles are in world space: object = world), h a vertex's height
//     above the root, w_d the direction, w_i the intensity, t the time:
//       φ = |P_x + P_z| mod 2π                                    spec/003 eq. 7.1
//       ω = 1 + φ/2π                                              spec/003 eq. 7.2
//       A = h·w_i·(ω − 1)                                         spec/003 eq. 7.3
//       w = w_d·h·w_i·(1 + A·sin(ωt + φ)),  w_y = 0               spec/003 eq. 7.4
//     w grows with h, so a root (h = 0) never moves.
// (b) The crossed billboards (spec/003 §2.9 b), one _Seed ∈ [0, 1] and one _SinSeed (the unit
//     centre's |x + z|) per unit, shared by all its planes:
//       φ = seed_sin                                              spec/003 eq. 7.13
//       ω = 1                                                     spec/003 eq. 7.14
//       A = I + seed                                              spec/003 eq. 7.15
//       s = (A/2)·sin(ωt + φ)                                     spec/003 eq. 7.16
//         = ((I + seed)/2)·sin(t + seed_sin)                      spec/003 eq. 7.17
//     (the document's scale factor is illegible; the repository's is 0.5), and a vertex at
//     texture height v moves by w_d·I·bend·size·v²·(steady + s): steady 1 the document's
//     (1 + s) — the geometry grass's form —, 3 the repository's h²·w_i·dir·(3 + s).
// (c) The instanced blades (beyond the thesis, Wohllaib 2021): the same w_d and w_i, plus a
//     gust field travelling with the wind (value noise of (x − W·t)/L, W the wind velocity).
//
// Failure cases guarded: a zero wind direction (no wind effect, all components 0) falls back to
// +x instead of normalize(0) = NaN; φ is taken of |P_x + P_z| with mod (never negative), so
// ω stays in [1, 2); the hashes are integer PCG hashes (no sin-of-large-number hash that loses
// its bits far from the origin); the gust noise wraps its lattice in integers.
// =============================================================================================

uniform vec3 uWindDir;        // w_d: (x, 0, z), the direction the wind blows toward
uniform float uWindIntensity; // w_i ∈ [0, 1] (min(|wind| / 20 m/s, 1) from the wind slot)
uniform vec2 uWindVelocity;   // (x, z) m/s: the gusts travel with it
uniform float uTime;          // t [s]
uniform vec3 uRipeness;       // cumulative chances of green, green + yellow, 1 (GrassGenerator)
uniform vec3 uBladeColor; // @param (0.16, 0.40, 0.06) [0, 1] color §2.9 Grass Color (Fig. 93): the
                          // albedo of the geometry-shader and instanced blades (linear; the
                          // repository's default is pure green; the billboards' tufts are painted
                          // around it)

const float GRASS_TWO_PI = 6.28318530717959;

vec3 GrassWindDirection() {
    vec3 d = vec3(uWindDir.x, 0.0, uWindDir.z);
    float len2 = dot(d, d);
    return len2 > 1e-12 ? d * inversesqrt(len2) : vec3(1.0, 0.0, 0.0);
}

// spec/003 eq. 7.1: φ = |P_x + P_z| mod 2π.
float GrassPhase(vec3 p) { return mod(abs(p.x + p.z), GRASS_TWO_PI); }

// spec/003 eq. 7.2: ω = 1 + φ/2π.
float GrassOmega(float phi) { return 1.0 + phi / GRASS_TWO_PI; }

// spec/003 eq. 7.3: A = h·w_i·(ω − 1).
float GrassAmplitude(float h, float omega) { return h * uWindIntensity * (omega - 1.0); }

// spec/003 eq. 7.4: w = w_d·h·w_i·(1 + A·sin(ωt + φ)), y zeroed.
vec3 GrassWindGS(float h, float phi, float omega) {
    float a = GrassAmplitude(h, omega);
    return GrassWindDirection() * (h * uWindIntensity * (1.0 + a * sin(omega * uTime + phi)));
}

// spec/003 eq. 7.13, spec/003 eq. 7.14, spec/003 eq. 7.15, spec/003 eq. 7.16, spec/003 eq. 7.17:
// s = ((I + seed)/2)·sin(ω t + seed_sin) with ω = 1.
float GrassBillboardSine(float seed, float sinSeed) {
    float phi = sinSeed;
    float omega = 1.0;
    float amp = uWindIntensity + seed;
    return 0.5 * amp * sin(omega * uTime + phi);
}

// The billboard vertex's offset at texture height v (module header (b)).
vec3 GrassBillboardWind(float v, float seed, float sinSeed, float size, float bend,
                        float steady) {
    float s = GrassBillboardSine(seed, sinSeed);
    return GrassWindDirection() * (uWindIntensity * bend * size * v * v * (steady + s));
}

// PCG hash (O'Neill 2014; Jarzynski and Olano 2020's pcg form): one 32-bit integer to another.
uint GrassHash(uint v) {
    uint state = v * 747796405u + 2891336453u;
    uint word = ((state >> ((state >> 28u) + 4u)) ^ state) * 277803737u;
    return (word >> 22u) ^ word;
}

// A float in [0, 1) from a hash.
float GrassUnit(uint h) { return float(h >> 8u) * (1.0 / 16777216.0); }

// The hash of a world position quantised to a millimetre (stable per blade).
uint GrassHashPosition(vec3 p) {
    ivec3 q = ivec3(floor(p * 1000.0));
    return GrassHash(uint(q.x) ^ GrassHash(uint(q.z) ^ GrassHash(uint(q.y))));
}

// Value noise in [0, 1] on the integer lattice (smoothstep-blended hashes).
float GrassValueNoise(vec2 p) {
    vec2 i = floor(p);
    vec2 f = p - i;
    ivec2 c = ivec2(i);
    float a = GrassUnit(GrassHash(uint(c.x) ^ GrassHash(uint(c.y))));
    float b = GrassUnit(GrassHash(uint(c.x + 1) ^ GrassHash(uint(c.y))));
    float d = GrassUnit(GrassHash(uint(c.x) ^ GrassHash(uint(c.y + 1))));
    float e = GrassUnit(GrassHash(uint(c.x + 1) ^ GrassHash(uint(c.y + 1))));
    vec2 w = f * f * (3.0 - 2.0 * f);
    return mix(mix(a, b, w.x), mix(d, e, w.x), w.y);
}

// The GrassGenerator's ripeness tint (GrassGenerator.cs: green → white, yellow, brown) for a
// random number r and the cumulative chances (green, green + yellow, 1) of the wellness.
vec3 GrassRipenessTint(float r, vec3 cumulative) {
    if (r < cumulative.x) return vec3(1.0);
    if (r < cumulative.y) return vec3(1.0, 0.92, 0.016);
    return vec3(1.0, 0.75, 0.25);
}
