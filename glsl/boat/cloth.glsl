// The sails' and the flag's cloth displacement — spec/000 §1.5: the thesis's vertex shader
// displaces each vertex by time-varying Perlin noise (TimeStep, TimeOffset, WaveHeight,
// WaveSpeed, WaveSize, GradientWeight per local axis); the belly of a filled sail is beyond
// the thesis. Numpy twin: app/sim/cloth.py (the formulas and their bounds are in its module
// docstring; this file follows it line for line).
//
// The cloth is a bilinear patch in its local frame (x chord or length, y up the luff or the
// hoist, z the flat normal): P(u, v) = lerp(lerp(P00, P01, v), lerp(P10, P11, v), u).
//   T      = TimeStep · t + TimeOffset
//   s      = WaveSize · u − WaveSpeed · T
//   D      = w · a · (WaveHeight · sin(2π s) · n + GradientWeight ⊙ N(q + o_i) / 1.0363538)
//          + Side · Fill · Camber · chord(v) · 4u(1 − u) · w · n,     a = mix(1, Taut, Fill)
//   with q = (s, WaveSize · v, T), N Perlin's improved noise, w the pinned weight.
// Normals: central differences of D with the step CLOTH_FD_STEP = 1/1024 in uv plus the
// patch's exact tangents; normal = normalize(S_u × S_v), turned to the flat normal's side.
//
// Failure cases guarded: held edges never move (every term carries w, which is 0 there; a
// sail's head row, collapsed into one point, is held so it cannot tear apart); a vanishing
// cross product (the collapsed head) falls back to the flat normal instead of a NaN; the noise
// is divided by its bound so |noise part| ≤ WaveHeight + |GradientWeight| (spec/000 §6
// criterion 35). Not guarded: float32 time — keep |T| below ~1e4 for a smooth phase.
#include "noise_perlin.glsl"

uniform float uTimeStep;        // TimeStep: cloth time T = uTimeStep · uTime + uTimeOffset
uniform float uTimeOffset;      // TimeOffset [s]
uniform float uWaveHeight;      // WaveHeight [m]
uniform float uWaveSpeed;       // WaveSpeed: ripples per unit of T
uniform float uWaveSize;        // WaveSize: ripples (and noise cells) across the mesh
uniform vec3 uGradientWeight;   // GradientWeight [m] along local x, y, z
uniform float uCamber;          // belly depth / chord at mid-chord, full sail
uniform float uTaut;            // share of ripple and noise left on a full sail
uniform float uBellySide;       // +1 or −1: the side (local ±z) the wind fills
uniform float uFill;            // 0 luffing … 1 full
uniform vec3 uCorner00;         // the patch: P(0,0), P(1,0), P(0,1), P(1,1), local frame
uniform vec3 uCorner10;
uniform vec3 uCorner01;
uniform vec3 uCorner11;
uniform vec4 uPinBand;          // hold widths in uv at u = 0, v = 0, u = 1, v = 1 (0: free)

const float CLOTH_FD_STEP = 1.0 / 1024.0;
const float CLOTH_TWO_PI = 6.28318530717959;
const float CLOTH_NOISE_BOUND = 1.0363538;  // PERLIN3_BOUND
const vec3 kClothNoiseOffset[3] = vec3[3](vec3(0.37, 0.61, 0.13), vec3(19.71, 43.29, 7.77),
                                          vec3(57.13, 11.83, 29.41));

float ClothTime(float t) { return uTimeStep * t + uTimeOffset; }

// The patch's chord (m) at height v [0, 1]: the distance between its u = 0 and u = 1 edges.
float ClothChord(float v) {
    return length(mix(uCorner10, uCorner11, v) - mix(uCorner00, uCorner01, v));
}

float ClothPinEdge(float dist, float band) {
    if (band <= 0.0) return 1.0;
    float r = clamp(dist / band, 0.0, 1.0);
    return 1.0 - (1.0 - r) * (1.0 - r);
}

// The pinned weight w(u, v): 0 on held edges, 1 in free cloth.
float ClothPinned(vec2 uv) {
    return ClothPinEdge(uv.x, uPinBand.x) * ClothPinEdge(uv.y, uPinBand.y)
         * ClothPinEdge(1.0 - uv.x, uPinBand.z) * ClothPinEdge(1.0 - uv.y, uPinBand.w);
}

// D in the local frame (m); the flat normal is local +z. uv in [0, 1]², w the pinned weight
// [0, 1] (every term carries it, so a held edge never moves), T the cloth time.
vec3 ClothDisplacement(vec2 uv, float w, float T) {
    float s = uWaveSize * uv.x - uWaveSpeed * T;
    float ripple = uWaveHeight * sin(CLOTH_TWO_PI * s);
    vec3 q = vec3(s, uWaveSize * uv.y, T);
    vec3 noise = vec3(PerlinNoise3(q + kClothNoiseOffset[0]),
                      PerlinNoise3(q + kClothNoiseOffset[1]),
                      PerlinNoise3(q + kClothNoiseOffset[2]))
               * (uGradientWeight / CLOTH_NOISE_BOUND);
    float fill = clamp(uFill, 0.0, 1.0);
    float a = 1.0 + fill * (uTaut - 1.0);
    vec3 d = noise * (w * a);
    float belly = uBellySide * fill * uCamber * ClothChord(uv.y) * 4.0 * uv.x * (1.0 - uv.x) * w;
    d.z += w * a * ripple + belly;
    return d;
}

// The displaced position (m) and unit normal (local frame) of a vertex at scene time t (s):
// D at uv, then central differences of D a step CLOTH_FD_STEP apart in u and in v, added to
// the patch's exact tangents, give S_u and S_v; normal = normalize(S_u × S_v), turned to the
// flat normal's side. The neighbours' pinned weights follow the vertex's own (pinned) by the
// change of ClothPinned across the step. Failure case: a vanishing cross product (the sail's
// collapsed head) falls back to the flat normal instead of a NaN.
void ClothSurface(vec3 position, vec3 flatNormal, vec2 uv, float pinned, float t,
                  out vec3 displaced, out vec3 normal) {
    float T = ClothTime(t);
    displaced = position + ClothDisplacement(uv, pinned, T);
    float base = ClothPinned(uv);
    float h = CLOTH_FD_STEP;
    vec2 du = vec2(h, 0.0), dv = vec2(0.0, h);
    float wu1 = clamp(pinned + ClothPinned(uv + du) - base, 0.0, 1.0);
    float wu0 = clamp(pinned + ClothPinned(uv - du) - base, 0.0, 1.0);
    float wv1 = clamp(pinned + ClothPinned(uv + dv) - base, 0.0, 1.0);
    float wv0 = clamp(pinned + ClothPinned(uv - dv) - base, 0.0, 1.0);
    vec3 left = mix(uCorner00, uCorner01, uv.y), right = mix(uCorner10, uCorner11, uv.y);
    vec3 pu = right - left;
    vec3 pv = mix(uCorner01 - uCorner00, uCorner11 - uCorner10, uv.x);
    vec3 su = pu + (ClothDisplacement(uv + du, wu1, T) - ClothDisplacement(uv - du, wu0, T))
                 / (2.0 * h);
    vec3 sv = pv + (ClothDisplacement(uv + dv, wv1, T) - ClothDisplacement(uv - dv, wv0, T))
                 / (2.0 * h);
    vec3 n = cross(su, sv);
    float len2 = dot(n, n);
    normal = len2 > 1e-24 ? n * inversesqrt(len2) : flatNormal;
    if (dot(normal, flatNormal) < 0.0) normal = -normal;
}
