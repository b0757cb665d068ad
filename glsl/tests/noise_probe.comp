#version 430
// Noise probe: evaluates one GLSL expression of the noise library at points read from a
// buffer and writes the results to another — how the tests (and accuracy benches) compare
// the GLSL noise with its numpy twin in app/sim/noise/. Driven by tests/helpers/noise_probe.py.
//
// The expression comes in as the define NOISE_FUNC (injected after #version by
// ShaderLibrary.program(name, defines={"NOISE_FUNC": ...})). It may use
//   P                   the point (vec4; unused components are 0),
//   uProbeSeed          uint seed (Worley sums),
//   uProbePeriod        ivec4 period (periodic noise),
//   uProbeOctaves       int, uProbeLacunarity float, uProbeGain float (fractal sums),
//   uProbeParams        vec4, free for other functions,
// and must give a float, vec2, vec3 or vec4 (stored as .x, .xy, .xyz or all of the vec4).
// Several functions can be probed at once: "vec4(PerlinNoise3(P.xyz), PerlinNoise2(P.xy),
// WorleyNoise3(P.xyz, uProbeSeed))". Perlin's permutation texture is bound to
// uPerlinPermutation by the driver.
//
// Other noise files (e.g. the thesis's value noise) are included by NoiseProbe(includes=...),
// which compiles a two-line wrapper that includes them and then this file.

layout(local_size_x = 64) in;

layout(std430, binding = 0) readonly buffer ProbePoints { vec4 probePoints[]; };
layout(std430, binding = 1) writeonly buffer ProbeResults { vec4 probeResults[]; };

uniform int uProbeFirst;   // index of the first point of this dispatch
uniform int uProbeCount;   // number of points in the buffers
uniform uint uProbeSeed;
uniform ivec4 uProbePeriod;
uniform int uProbeOctaves;
uniform float uProbeLacunarity;
uniform float uProbeGain;
uniform vec4 uProbeParams;

#include "noise_perlin.glsl"
#include "noise_worley.glsl"
#include "noise_fbm.glsl"

#ifndef NOISE_FUNC
#define NOISE_FUNC PerlinNoise3(P.xyz)
#endif

vec4 ProbeResult(float v) { return vec4(v, 0.0, 0.0, 0.0); }
vec4 ProbeResult(vec2 v) { return vec4(v, 0.0, 0.0); }
vec4 ProbeResult(vec3 v) { return vec4(v, 0.0); }
vec4 ProbeResult(vec4 v) { return v; }

void main() {
    int i = uProbeFirst + int(gl_GlobalInvocationID.x);
    if (i >= uProbeCount) return;
    vec4 P = probePoints[i];
    probeResults[i] = ProbeResult(NOISE_FUNC);
}
