#version 330 core
// =============================================================================================
// Amortised layer, the resolve (beyond the theses; after Schneider 2015, "The real-time
// volumetric cloudscapes of Horizon: Zero Dawn": a fraction of the pixels is marched per frame,
// the rest reprojected). Python: app/render/amortise.py; numpy twins: app/sim/amortise.py
// (fill, fill_nearest, depth_agree). One full-resolution pass per frame; for each pixel p:
//   1. near cut: the opaque scene is nearer than the layer can be (uNearCloud: the camera's
//      distance to the cloud container) → exactly no cloud, (0, 0, 0, 1) — the boat, its mast
//      and the near sea never take a cloud from a neighbour;
//   2. marched this frame (p = t·B + sub) → the fresh march of p itself;
//   3. otherwise, by AMORTISE_PATH (one program each: a software renderer runs every branch of
//      a shader with masks, so a path's cost is all the code it holds):
//      0 (reset: no history) — fill: the fresh marches of the 4 nearest grid points, bilinear
//        weights, those whose scene distance disagrees dropped (depth-aware upsampling: clouds
//        do not bleed over a mast or across the horizon); none left → the one of the nearest
//        distance;
//      1 (still: camera and field where they were) — p's own history texel, bit for bit, if
//        its scene distance agrees with p's; else (disocclusion) the nearest-depth fresh grid
//        point (of the 4 nearest, the one whose distance is closest to p's);
//      2 (moving) — reprojection: the point at p's last cloud distance (the history's, at p),
//        moved back by the field's shift since the last frame (the wind), projected with the
//        last camera (camera-relative: uCameraDelta = this camera − the last). The history is
//        read there bilinearly if the bilinear scene distance equals the nearest texel's (the
//        four texels are one surface), else at the nearest texel; kept if that texel's scene
//        distance agrees with p's, else (disocclusion, off the last frame, behind its camera)
//        the history at p itself if p shows an opaque surface within the layer's reach
//        (uFarCloud) whose distance agrees with its texel's (an object that moved with the
//        view, such as a boat the camera follows: no neighbour's cloud bleeds onto it), else
//        the nearest-depth fresh grid point as in 1.
// Scene distances are compared clipped at uFarCloud (two rays past the layer's far reach, the
// sky and the far sea at the horizon, see the same nothing), by AmortiseDepthAgree.
// Outputs: the layer (rgb premultiplied radiance, a transmittance), and aux = (cloud distance,
// clipped scene distance, how much of the value was marched at the pixel (1) rather than
// filled (0), 0) for the next frame.
// Failure cases guarded: a never-marched cloud distance (0) counts as far; the projection's
// w ≤ 0 (behind the last camera) and a point off the last frame by more than half a pixel are
// rejected; taps off the image are clamped; grid points whose pixel lies off the image are
// moved back inside.
// =============================================================================================
#include "camera.glsl"
#include "amortise.glsl"

#ifndef AMORTISE_PATH
#define AMORTISE_PATH 0
#endif

in vec2 vUV;
layout(location = 0) out vec4 outLayer;
layout(location = 1) out vec4 outAux;

uniform sampler2D uFresh;         // this frame's marches, one per B×B block (grid texels)
uniform sampler2D uFreshAux;      // their (cloud distance, scene distance)
uniform sampler2D uHistory;       // last frame's resolved layer (full resolution, bilinear)
uniform sampler2D uHistoryAux;    // last frame's aux (bilinear)
uniform sampler2D uSceneDepth;    // this frame's window depth (compare mode off)
uniform bool uHasSceneDepth;
uniform float uCamNear;
uniform float uCamFar;
uniform mat4 uPrevViewProj;       // the last frame's projection × view, camera-relative
uniform vec3 uCameraDelta;        // this camera's position − the last one's (metres)
uniform vec3 uFieldShift;         // how far the field moved since the last frame (metres)
uniform float uNearCloud;         // no cloud nearer than this (metres)
uniform float uFarCloud;          // nor farther than this

float SceneDistance(ivec2 p, vec3 dir) {
    if (!uHasSceneDepth) return uFarCloud;
    float depth = texelFetch(uSceneDepth, p, 0).r;
    if (depth >= 1.0) return uFarCloud;
    float z = depth * 2.0 - 1.0;
    float viewZ = 2.0 * uCamNear * uCamFar / (uCamFar + uCamNear - z * (uCamFar - uCamNear));
    return min(viewZ / max(dot(dir, uCamForward), 1.0e-6), uFarCloud);
}

// The grid point (texel) of corner (dx, dy) of the grid cell around p, and its weight.
ivec2 GridTap(ivec2 p, int dx, int dy, out float weight) {
    int b = max(uAmortiseBlock, 1);
    ivec2 gridSize = textureSize(uFresh, 0);
    ivec2 lastInside = max(ivec2(uAmortiseFullSize) - 1 - uAmortiseSub, ivec2(0)) >> uAmortiseShift;
    vec2 g = vec2(p - uAmortiseSub) / float(b);
    ivec2 g0 = ivec2(floor(g));
    vec2 f = g - vec2(g0);
    weight = (dx == 1 ? f.x : 1.0 - f.x) * (dy == 1 ? f.y : 1.0 - f.y);
    return min(clamp(g0 + ivec2(dx, dy), ivec2(0), gridSize - 1), lastInside);
}

#if AMORTISE_PATH == 0
// The depth-aware bilinear interpolation of the fresh grid at p (twin: app.sim.amortise.fill).
void AmortiseFill(ivec2 p, float dist, out vec4 layer, out float cloudDist) {
    vec4 sum = vec4(0.0);
    float sumDist = 0.0, weight = 0.0;
    vec4 best = vec4(0.0, 0.0, 0.0, 1.0);
    float bestDist = AMORTISE_FAR, bestDelta = 1.0e38;
    for (int dy = 0; dy <= 1; ++dy) {
        for (int dx = 0; dx <= 1; ++dx) {
            float w;
            ivec2 t = GridTap(p, dx, dy, w);
            vec4 v = texelFetch(uFresh, t, 0);
            vec2 aux = texelFetch(uFreshAux, t, 0).xy;
            float d = min(aux.y, uFarCloud);
            float delta = abs(d - dist);
            if (delta < bestDelta) {
                bestDelta = delta;
                best = v;
                bestDist = aux.x;
            }
            if (w > 0.0 && AmortiseDepthAgree(dist, d)) {
                sum += w * v;
                sumDist += w * aux.x;
                weight += w;
            }
        }
    }
    if (weight > 1.0e-6) {
        layer = sum / weight;
        cloudDist = sumDist / weight;
    } else {
        layer = best;
        cloudDist = bestDist;
    }
}
#else
// The nearest-depth fresh grid point of the 4 around p (twin: app.sim.amortise.fill_nearest).
void AmortiseFillNearest(ivec2 p, float dist, out vec4 layer, out float cloudDist) {
    ivec2 best = ivec2(0);
    float bestDelta = 1.0e38;
    cloudDist = AMORTISE_FAR;
    for (int dy = 0; dy <= 1; ++dy) {
        for (int dx = 0; dx <= 1; ++dx) {
            float w;
            ivec2 t = GridTap(p, dx, dy, w);
            vec2 aux = texelFetch(uFreshAux, t, 0).xy;
            float delta = abs(min(aux.y, uFarCloud) - dist) - 1.0e-3 * w;  // ties: the nearer
            if (delta < bestDelta) {
                bestDelta = delta;
                best = t;
                cloudDist = aux.x;
            }
        }
    }
    layer = texelFetch(uFresh, best, 0);
}
#endif

void main() {
    ivec2 p = ivec2(gl_FragCoord.xy);
    vec3 dir = CameraRayDirection(vUV);
    float dist = SceneDistance(p, dir);
    vec4 layer;
    vec4 aux;
    bool kept = false;  // a value from the history
#if AMORTISE_PATH == 1
    aux = texelFetch(uHistoryAux, p, 0);
    layer = texelFetch(uHistory, p, 0);
    kept = AmortiseDepthAgree(dist, aux.y);
#elif AMORTISE_PATH == 2
    float t = texelFetch(uHistoryAux, p, 0).x;
    t = t > 0.0 ? min(t, AMORTISE_FAR) : AMORTISE_FAR;
    vec3 rel = uCameraDelta + dir * t - uFieldShift;  // relative to the last camera
    vec4 clip = uPrevViewProj * vec4(rel, 1.0);
    vec2 uv = clip.xy / max(clip.w, 1.0e-30) * 0.5 + 0.5;
    vec2 xy = uv * uAmortiseFullSize;
    ivec2 q = clamp(ivec2(floor(xy)), ivec2(0), ivec2(uAmortiseFullSize) - 1);
    aux = texelFetch(uHistoryAux, q, 0);
    float mixed = texture(uHistoryAux, uv).y;  // one surface under the 4 texels: no edge
    layer = AmortiseDepthAgree(mixed, aux.y) ? texture(uHistory, uv) : texelFetch(uHistory, q, 0);
    kept = clip.w > 0.0 && all(greaterThanEqual(xy, vec2(-0.5)))
        && all(lessThanEqual(xy, uAmortiseFullSize + 0.5)) && AmortiseDepthAgree(dist, aux.y);
    if (!kept && dist < uFarCloud) {  // a surface that moved with the view: its own texel
        vec4 own = texelFetch(uHistoryAux, p, 0);
        if (AmortiseDepthAgree(dist, own.y)) {
            aux = own;
            layer = texelFetch(uHistory, p, 0);
            kept = true;
        }
    }
#endif
    ivec2 g = p - uAmortiseSub;
    ivec2 gt = g >> uAmortiseShift;
    bool fresh = all(greaterThanEqual(g, ivec2(0))) && all(equal(gt << uAmortiseShift, g));
    vec4 freshLayer = texelFetch(uFresh, gt, 0);
    float freshDist = texelFetch(uFreshAux, gt, 0).x;
    vec4 filled;
    float filledDist;
#if AMORTISE_PATH == 0
    AmortiseFill(p, dist, filled, filledDist);
#else
    AmortiseFillNearest(p, dist, filled, filledDist);
#endif
    if (dist < uNearCloud) {  // 1. nothing between the camera and the opaque scene
        outLayer = vec4(0.0, 0.0, 0.0, 1.0);
        outAux = vec4(AMORTISE_FAR, dist, 1.0, 0.0);
    } else if (fresh) {  // 2. marched now
        outLayer = freshLayer;
        outAux = vec4(freshDist, dist, 1.0, 0.0);
    } else if (kept) {  // 3. the history
        outLayer = layer;
        outAux = vec4(aux.x, dist, aux.z, 0.0);
    } else {  // 3. filled from this frame's marches
        outLayer = filled;
        outAux = vec4(filledDist, dist, 0.0, 0.0);
    }
}
