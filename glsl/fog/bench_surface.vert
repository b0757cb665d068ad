#version 330 core
// A constant-colour surface under the global fog (spec/003 §2.11 b): the ground and the quads
// of the fog's bench (app/bench/village_fog.py) and tests. World-space vertices; the factor per
// vertex (fog.glsl: spec/003 eq. 7.24, spec/003 eq. 7.27, spec/003 eq. 7.28, spec/003 eq. 7.29)
// rides in the w of the world position, as the thesis packs it.
// Failure cases guarded: none of its own — those guarded are fog.glsl's (its header).
#include "fog.glsl"

in vec3 in_position;

uniform mat4 uViewProj;

out vec4 vWorldPos;

void main() {
    gl_Position = uViewProj * vec4(in_position, 1.0);
    vWorldPos = vec4(in_position, FogVertexFactor(gl_Position));
}
