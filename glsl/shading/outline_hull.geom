#version 330 core
// The inverted-hull outline of spec/003 §2.13: the geometry shader of the thesis's extra pass.
// Each triangle is emitted displaced along its vertices' normals (computed in world space, then
// taken to clip space), drawn with front faces culled after the object, so only the shell's
// back faces show, as a rim of outline colour around the silhouette.
//
// Width (screen-stable): uWidthPx is in pixels. A vertex at view depth w (its clip w) moves
// uWidthPx · uPixelWorld · w metres along its unit normal, where uPixelWorld = 2 / (P[1][1] · H)
// is the world size of one pixel at unit depth (P the projection, H the target's height): the
// outline is uWidthPx pixels wide where the normal lies across the view ray, whatever the
// distance, and narrower where the normal is foreshortened. Orthographic projections (clip w = 1)
// get the same pixel width. uWidthPx ≤ 0 emits nothing (no outline, and no shell z-fighting
// the object's own back faces).
//
// Failure cases guarded: a vertex behind the camera (clip w ≤ 0) is not extruded (its depth
// is clamped to 1e-4 m); a zero normal (degenerate mesh) is not extruded either. The thesis's
// own failure is kept on purpose: with per-vertex (faceted) normals the shell of a low-poly mesh
// opens at hard edges and corners (gaps, Fig. 133b); uSmoothNormals in outline_hull.vert closes
// it.
layout(triangles) in;
layout(triangle_strip, max_vertices = 3) out;

in vec3 gWorldPos[];
in vec3 gWorldNormal[];

uniform mat4 uViewProj;
uniform float uWidthPx;      // outline width, pixels
uniform float uPixelWorld;   // world size of one pixel at unit view depth: 2 / (P[1][1] · H)

void main() {
    if (uWidthPx <= 0.0) return;
    for (int i = 0; i < 3; ++i) {
        vec3 p = gWorldPos[i];
        float w = max((uViewProj * vec4(p, 1.0)).w, 1e-4);
        float len = length(gWorldNormal[i]);
        vec3 n = len > 1e-8 ? gWorldNormal[i] / len : vec3(0.0);
        gl_Position = uViewProj * vec4(p + n * (uWidthPx * uPixelWorld * w), 1.0);
        EmitVertex();
    }
    EndPrimitive();
}
