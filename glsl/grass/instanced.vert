#version 330 core
// Instanced procedural blades (beyond the thesis; Wohllaib 2021, "Procedural Grass in Ghost of
// Tsushima", GDC): the grass of spec/003 §2.9 drawn a third way, program
// ProgramSpec("grass/instanced"): this file + instanced.frag. One instanced strip mesh
// (app/sim/grass.py blade_strip: segments along the blade, two vertices per level, the tip a
// single vertex) drawn once per blade; per blade, from hashes of its id: height, facing, static
// lean, flutter phase and speed, width and ripeness. The blade's spine is a cubic Bézier
//   B(t) = (1−t)³P0 + 3(1−t)²t P1 + 3(1−t)t² P2 + t³P3,
// P0 the root, P1 straight above it (a stiff base), P3 the tip leaned by o = lean·front +
// bend·w_d (in blade heights, |o| ≤ 0.95) at the height √(1 − |o|²) that keeps the chord, P2
// between; the width tapers as (1 − t)^0.7 to the tip. The wind is the scene's one wind
// (grass_wind.glsl: w_d and w_i, as the thesis's methods take it) plus a gust field travelling
// with the wind velocity (value noise of (x − W·t)/L) and a per-blade flutter. The normal is
// cross(side, B'(t)), tilted across the width for a rounded look (Wohllaib 2021). Blades fade
// out (their height to 0) over the last 20 % of the draw distance when culling, so the tiles
// the CPU culls beyond it do not pop.
// Failure cases guarded: the tip's lean is capped below the blade's height (no sqrt of a
// negative, no blade folding into the ground); a zero Bézier derivative (a blade of height 0)
// falls back to +y; pow(1 − t, 0.7) is only taken of t ≤ 1; a zero wind direction is +x.
#include "math.glsl"
#include "fog.glsl"
#include "grass_wind.glsl"

in vec2 in_blade;   // (t along the blade, side −1 / 0 / +1)
in vec4 in_root;    // xyz the root on the ground, w the blade's id (per instance)

uniform mat4 uViewProj;
uniform vec3 uCameraPos;
uniform float uBladeHeight;   // mean height [m]
uniform float uBladeWidth;    // mean width at the root [m]
uniform float uDrawDistance;  // [m]
uniform bool uFade;           // fade out toward the draw distance (culling on)
uniform float uGust; // @param 0.6 [0, 1] step=0.01 §2.9 instanced blades: strength of the gusts
                     // travelling with the wind
uniform float uGustScale; // @param 9 [1, 60] step=0.5 unit=m §2.9 instanced blades: size of a gust

out vec4 vWorldPos;
out vec3 vNormal;
out vec3 vAlbedo;

void main() {
    vec3 root = in_root.xyz;
    uint h0 = GrassHash(uint(max(in_root.w, 0.0)));
    uint h1 = GrassHash(h0 ^ 0x9E3779B9u);
    uint h2 = GrassHash(h1), h3 = GrassHash(h2), h4 = GrassHash(h3), h5 = GrassHash(h4);
    uint h6 = GrassHash(h5);
    float height = max(uBladeHeight, 0.0) * mix(0.6, 1.25, GrassUnit(h0));
    if (uFade) {
        float dist = length(root - uCameraPos);
        height *= 1.0 - smoothstep(0.8 * uDrawDistance, uDrawDistance, dist);
    }
    float facing = GRASS_TWO_PI * GrassUnit(h1);
    vec3 side = vec3(cos(facing), 0.0, sin(facing));
    vec3 front = vec3(-side.z, 0.0, side.x);
    float lean = mix(0.08, 0.35, GrassUnit(h2));
    float gust = GrassValueNoise((root.xz - uWindVelocity * uTime) / max(uGustScale, 1e-3));
    float flutter = sin(uTime * mix(2.0, 5.0, GrassUnit(h3)) + GRASS_TWO_PI * GrassUnit(h4));
    float bend = uWindIntensity * (0.8 + clamp(uGust, 0.0, 1.0) * (2.0 * gust - 1.0) * 0.7
                                   + 0.12 * flutter);
    vec3 o = lean * front + max(bend, 0.0) * GrassWindDirection();
    float lo = length(o);
    if (lo > 0.95) o *= 0.95 / lo;
    float cy = sqrt(max(1.0 - dot(o, o), 0.0));
    vec3 yv = vec3(0.0, 1.0, 0.0);
    vec3 p0 = root;
    vec3 p1 = root + yv * (0.45 * height);
    vec3 p2 = root + (yv * (0.85 * cy) + 0.45 * o) * height;
    vec3 p3 = root + (yv * cy + o) * height;
    float t = clamp(in_blade.x, 0.0, 1.0);
    float s = 1.0 - t;
    vec3 b = s * s * s * p0 + 3.0 * s * s * t * p1 + 3.0 * s * t * t * p2 + t * t * t * p3;
    vec3 db = 3.0 * s * s * (p1 - p0) + 6.0 * s * t * (p2 - p1) + 3.0 * t * t * (p3 - p2);
    float width = max(uBladeWidth, 0.0) * mix(0.7, 1.3, GrassUnit(h5)) * pow(s, 0.7);
    vec3 p = b + side * (0.5 * width * in_blade.y);
    vec3 tangent = SafeNormalize(db, yv);
    vec3 n = SafeNormalize(cross(side, tangent), front);
    n = SafeNormalize(n + side * (0.35 * in_blade.y), n);
    gl_Position = uViewProj * vec4(p, 1.0);
    vWorldPos = vec4(p, FogVertexFactor(gl_Position));
    vNormal = n;
    vAlbedo = uBladeColor * GrassRipenessTint(GrassUnit(h6), uRipeness) * mix(0.55, 1.0, t)
            * (0.85 + 0.3 * GrassUnit(h5 ^ h2));
}
