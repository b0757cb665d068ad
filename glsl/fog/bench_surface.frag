#version 330 core
// A constant-colour surface under the global fog (spec/003 §2.11 b): bench_surface.vert + this
// file. colour = FogApply(uObjectColor, …) = lerp(fogColour, objColour, f) (fog.glsl:
// spec/003 eq. 7.27, spec/003 eq. 7.28, spec/003 eq. 7.29; Quílez 2010 with uFogHeight); alpha
// carries the fragment's view depth 1/gl_FragCoord.w for a float target (with fog colour 0 and
// object colour 1 the red channel is the factor f itself, what the bench compares).
// Failure cases guarded: none of its own — those guarded are fog.glsl's (its header).
#include "fog.glsl"

in vec4 vWorldPos;

uniform vec3 uObjectColor;

out vec4 fragColor;

void main() {
    fragColor = vec4(FogApply(uObjectColor, vWorldPos.w, vWorldPos.xyz), 1.0 / gl_FragCoord.w);
}
