#version 330 core
// Instanced procedural blades (beyond the thesis; Wohllaib 2021) for spec/003 §2.9: the
// fragment stage of ProgramSpec("grass/instanced") — the same diffuse-only light as the
// thesis's grass (grass_shading.glsl), plus a little translucency (light through the blade from
// behind, uTranslucency), the sun's shadow received, the global fog after the lighting
// (fog.glsl: spec/003 eq. 7.27, spec/003 eq. 7.28, spec/003 eq. 7.29).
// Failure cases guarded: in grass_shading.glsl (the blade's back lit as its visible side, a
// zero normal, the light below the horizon); a negative translucency is clamped there.
#include "grass_shading.glsl"

in vec4 vWorldPos;
in vec3 vNormal;
in vec3 vAlbedo;

uniform float uTranslucency; // @param 0.3 [0, 1] step=0.01 §2.9 instanced blades: light through the
                             // blade from behind (beyond the thesis's diffuse-only shading)

out vec4 fragColor;

void main() {
    fragColor = vec4(GrassShade(vAlbedo, vNormal, vWorldPos, uTranslucency), 1.0);
}
