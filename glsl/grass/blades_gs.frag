#version 330 core
// The thesis's geometry-shader grass (spec/003 §2.9 a): the fragment stage of
// ProgramSpec("grass/blades_gs") — the face normal from the geometry stage, diffuse light only
// (grass_shading.glsl: the document's Lambert plus the sky's ambient, or the repository's
// _LightColor0·_Color·(0.5 + 0.5·saturate(n·l))), the sun's shadow received, the global fog
// after the lighting (spec/003 eq. 7.27, spec/003 eq. 7.28, spec/003 eq. 7.29 in fog.glsl).
// Failure cases guarded: in grass_shading.glsl (a face seen from behind lit as its visible
// side, a zero normal, the light below the horizon).
#include "grass_shading.glsl"

in vec4 fWorldPos;
in vec3 fNormal;
flat in vec3 fAlbedo;

out vec4 fragColor;

void main() {
    fragColor = vec4(GrassShade(fAlbedo, fNormal, fWorldPos, 0.0), 1.0);
}
