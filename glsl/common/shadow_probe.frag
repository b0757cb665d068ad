#version 330 core
// The shadow receivers evaluated at given points (spec/003 §2.8), program
// fullscreen("common/shadow_probe"): common/fullscreen.vert + this file. Each output texel reads
// a world position (xyz) and view depth (w) from uPoints and a normal from uNormals and writes
// ShadowSun / ShadowSpot / ShadowPoint (uLight 0 / 1 / 2) and ShadowCascade — how the tests and
// the bench measure the shared receivers against app/sim/surfaces_scene.py's exact visibility.
// Equations: none of its own (shadow.glsl's).
// Failure cases guarded: a texel whose normal's w < 0.5 (no point there) writes −1, never a
// visibility.
in vec2 vUV;
uniform sampler2D uPoints;
uniform sampler2D uNormals;
uniform int uLight;
out vec4 fragColor;

#include "shadow.glsl"

void main() {
    ivec2 px = ivec2(gl_FragCoord.xy);
    vec4 p = texelFetch(uPoints, px, 0);
    vec4 nn = texelFetch(uNormals, px, 0);
    vec3 n = nn.xyz;
    if (nn.w < 0.5) { fragColor = vec4(-1.0); return; }
    float v = uLight == 0 ? ShadowSun(p.xyz, n, p.w)
            : uLight == 1 ? ShadowSpot(p.xyz, n) : ShadowPoint(p.xyz, n);
    fragColor = vec4(v, float(ShadowCascade(p.w)), 0.0, 1.0);
}
