#version 330 core
// The lit surface of the shading lab (spec/003 §2.1, spec/003 §2.12): the vertex stage. The
// models, the toon modes, the forward light sum and their equations are in lighting.glsl, which
// both stages include; the program's interface is documented in surface.frag.
// Gouraud (uGouraud): the whole surface is lit here, per vertex, and the colour interpolated —
// the method the thesis rejects (spec/003 §0: per-fragment lighting looks "much better"): a
// highlight smaller than a triangle is missed or smeared into the triangle's shape.
// Failure cases guarded: normals transformed by mat3(uModel), exact only because uModel is
// limited to rotation, translation and uniform scale (a non-uniform scale would need the inverse
// transpose); a zero normal or a vertex at the camera fall back to safe unit vectors
// (SafeNormalize); the masks are read with textureLod (no derivatives in a vertex shader).
#include "lighting.glsl"

in vec3 in_position;
in vec3 in_normal;
in vec2 in_uv;
in vec4 in_tangent;        // xyz the tangent (direction of +u), w the handedness (±1)

uniform mat4 uModel;       // rotation, translation and uniform scale only
uniform mat4 uViewProj;
uniform vec3 uCameraPos;
uniform bool uGouraud; // @param false §2.1 Gouraud: light per vertex and interpolate (the thesis
                       // lights per fragment)

out vec3 vWorldPos;
out vec3 vWorldNormal;
out vec4 vWorldTangent;
out vec2 vUV;
out vec3 vGouraud;         // the per-vertex colour (only meaningful with uGouraud)

void main() {
    vec4 world = uModel * vec4(in_position, 1.0);
    vWorldPos = world.xyz;
    vWorldNormal = mat3(uModel) * in_normal;
    vWorldTangent = vec4(mat3(uModel) * in_tangent.xyz, in_tangent.w);
    vUV = in_uv;
    vGouraud = vec3(0.0);
    if (uGouraud) {
        vec3 v = SafeNormalize(uCameraPos - vWorldPos, vec3(0.0, 0.0, 1.0));
        vec3 n = SafeNormalize(vWorldNormal, v);
        vec4 masks = uUseMasks ? textureLod(uMasks, in_uv, 0.0) : vec4(0.0, 1.0, 0.0, 0.0);
        vGouraud = ShadeSurface(vWorldPos, n, v, uAlbedo, masks.g, masks.r);
    }
    gl_Position = uViewProj * world;
}
