#version 330 core
// The thesis's geometry-shader grass (spec/003 §2.9 a): one "pyramid" blade per input triangle.
// Defines: GS_SECTIONS (S, 1..4: the repository's _Sections range) and GS_MAX_VERTICES (its
// declared output, 3·(6(S − 1) + 3): every triangle is its own strip; the repository declared
// maxvertexcount(92) for all S). app/sim/grass.py's gs_blade is the numpy twin, vertex for
// vertex.
//
// The blade: the base is first shrunk halfway toward the centroid P (the repository's "make the
// bottom slimmer"; uShrinkBase). Each section moves the ring's three vertices toward the ring's
// centroid by (centroid − vertex)/S and up by height/S: six triangles join two rings; the last
// section closes with three triangles to the apex, so 6(S − 1) + 3 triangles per input
// triangle. Every vertex is then displaced by the wind w of spec/003 eq. 7.4 taken at its own
// height above the root (phase spec/003 eq. 7.1 and angular speed spec/003 eq. 7.2 of P,
// amplitude spec/003 eq. 7.3): the base ring (h = 0) never moves, the apex moves by w(height),
// in the xz plane only. Face normals are cross products of each emitted triangle's edges,
// oriented away from the blade's axis (Fig. 89). uRepositoryHeight adds ω Unity units to the
// height, the repository's (_Height + ω)/_Sections (a per-blade height variation). With culling
// on (the effect's tiles), a blade shrinks to nothing over the last 20 % of the draw distance.
//
// Failure cases guarded: a degenerate face (height 0, a zero-area root triangle) gets the +y
// normal instead of normalize(0) = NaN; a negative height is clamped to 0; the section count is
// a compile-time constant (the loop bound and max_vertices agree, so no vertex is ever dropped).
#include "math.glsl"
#include "fog.glsl"
#include "grass_wind.glsl"

#ifndef GS_SECTIONS
#define GS_SECTIONS 3
#endif
#ifndef GS_MAX_VERTICES
#define GS_MAX_VERTICES 45
#endif

layout(triangles) in;
layout(triangle_strip, max_vertices = GS_MAX_VERTICES) out;

in vec3 gPosition[];

uniform mat4 uViewProj;
uniform float uHeight;            // the blade's height [m] (Fig. 93's 4.87 Unity units = 0.487 m)
uniform bool uShrinkBase;         // the repository's halfway shrink of the base
uniform bool uRepositoryHeight;   // the repository's height + ω Unity units
uniform vec3 uCameraPos;
uniform bool uFade;               // culling on: blades shrink to nothing over the last 20 % of
uniform float uDrawDistance;      // the draw distance [m] (beyond it their tile is not drawn)

out vec4 fWorldPos;   // xyz world position, w the fog factor of the vertex
out vec3 fNormal;
flat out vec3 fAlbedo;

const float UNITY_UNIT = 0.1;  // metres per Unity unit (app/sim/grass.py)

// Emits the triangle (a, b, c), world positions in metres, with its flat normal turned away
// from the blade's axis point `axis` (outward), the fog factor of each vertex and the
// blade's albedo. A degenerate triangle (zero cross product) gets the normal +y.
void EmitFace(vec3 a, vec3 b, vec3 c, vec3 axis, vec3 albedo) {
    vec3 n = SafeNormalize(cross(b - a, c - a), vec3(0.0, 1.0, 0.0));
    if (dot(n, (a + b + c) / 3.0 - axis) < 0.0) n = -n;
    vec3 corners[3] = vec3[3](a, b, c);
    for (int i = 0; i < 3; ++i) {
        gl_Position = uViewProj * vec4(corners[i], 1.0);
        fWorldPos = vec4(corners[i], FogVertexFactor(gl_Position));
        fNormal = n;
        fAlbedo = albedo;
        EmitVertex();
    }
    EndPrimitive();
}

void main() {
    vec3 t[3] = vec3[3](gPosition[0], gPosition[1], gPosition[2]);
    vec3 p = (t[0] + t[1] + t[2]) / 3.0;
    float phi = GrassPhase(p);
    float omega = GrassOmega(phi);
    uint h = GrassHashPosition(p);
    vec3 albedo = uBladeColor * GrassRipenessTint(GrassUnit(h), uRipeness)
                * (0.85 + 0.3 * GrassUnit(GrassHash(h)));
    float height = max(uHeight, 0.0) + (uRepositoryHeight ? omega * UNITY_UNIT : 0.0);
    if (uFade) {
        height *= 1.0 - smoothstep(0.8 * uDrawDistance, uDrawDistance, length(p - uCameraPos));
    }
    float s = float(GS_SECTIONS);
    vec3 up = vec3(0.0, height / s, 0.0);
    vec3 rest[3];   // the lower ring at rest
    vec3 lower[3];  // the lower ring, moved by the wind
    for (int i = 0; i < 3; ++i) {
        rest[i] = uShrinkBase ? (p + t[i]) * 0.5 : t[i];
        lower[i] = rest[i];  // h = 0: w = 0
    }
    for (int k = 1; k < GS_SECTIONS; ++k) {
        vec3 c = (rest[0] + rest[1] + rest[2]) / 3.0;
        vec3 w = GrassWindGS(float(k) * height / s, phi, omega);
        vec3 nextRest[3];
        vec3 upper[3];
        for (int i = 0; i < 3; ++i) {
            nextRest[i] = rest[i] + (c - rest[i]) / s + up;
            upper[i] = nextRest[i] + w;
        }
        vec3 axis = ((lower[0] + lower[1] + lower[2]) + (upper[0] + upper[1] + upper[2])) / 6.0;
        for (int i = 0; i < 3; ++i) {
            int j = (i + 1) % 3;
            EmitFace(lower[i], upper[j], upper[i], axis, albedo);
            EmitFace(lower[i], lower[j], upper[j], axis, albedo);
        }
        for (int i = 0; i < 3; ++i) {
            rest[i] = nextRest[i];
            lower[i] = upper[i];
        }
    }
    vec3 apex = (rest[0] + rest[1] + rest[2]) / 3.0 + up + GrassWindGS(height, phi, omega);
    vec3 axis = ((lower[0] + lower[1] + lower[2]) / 3.0 + apex) * 0.5;
    for (int i = 0; i < 3; ++i) EmitFace(lower[i], lower[(i + 1) % 3], apex, axis, albedo);
}
