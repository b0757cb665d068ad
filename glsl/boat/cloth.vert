#version 330 core
// Sails and flag, vertex stage — the maritime thesis's cloth shader (spec/000 §1.5): the
// vertices of a flat cloth patch are displaced by time-varying Perlin noise and a ripple
// (TimeStep, TimeOffset, WaveHeight, WaveSpeed, WaveSize, GradientWeight per local axis), and
// a filled sail takes a parabolic belly (beyond the thesis). Equations: the displacement and
// its normal are written out in cloth.glsl (numpy twin app/sim/cloth.py); the thesis numbers
// none.
// Failure cases guarded: held edges (luff, foot, head, the flag's hoist) never move; no NaN
// normal at a sail's collapsed head (flat normal instead); normals are transformed by
// mat3(uModel), exact only because uModel is limited to rotation, translation and uniform
// scale (a mirror is allowed: the fragment stage corrects its facing).
#include "cloth.glsl"

in vec3 in_position;  // local frame of the cloth (z its flat normal)
in vec3 in_normal;    // the flat normal, local +z
in vec2 in_uv;        // (u, v) of the patch, also the texture coordinates
in float in_pinned;   // 0 held … 1 free cloth

uniform mat4 uModel;     // world ← cloth local: world ← boat times the mesh's transform
uniform mat4 uViewProj;
uniform float uTime;     // scene time [s]

out vec3 vWorldPos;
out vec3 vWorldNormal;
out vec2 vUV;

void main() {
    vec3 p, n;
    ClothSurface(in_position, in_normal, in_uv, in_pinned, uTime, p, n);
    vec4 world = uModel * vec4(p, 1.0);
    vWorldPos = world.xyz;
    vWorldNormal = mat3(uModel) * n;
    vUV = in_uv;
    gl_Position = uViewProj * world;
}
