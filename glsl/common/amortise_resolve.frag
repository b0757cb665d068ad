#version 330 core
// Amortised layer, the resolve (beyond the theses; after Schneider 2015, the clouds of Horizon:
// Zero Dawn: a fraction of the pixels is marched per frame, the rest reprojected). Python:
// app/render/amortise.py; numpy twins: app/sim/amortise.py (fill, fill_nearest, depth_agree).
// Two full-resolution passes per frame: the near cut (AMORTISE_NEAR) writes the pixels whose
// opaque scene is nearer than the layer and leaves a depth mark there; then the resolve proper,
// one program per AMORTISE_PATH (0 reset, 1 still, 2 moving), is depth-tested against the mark.
// A software renderer runs every line of a shader with masks, taken or not (so a path's cost is
// all the code it holds), but it skips a block of fragments the depth test rejects: in a
// maritime frame most pixels are the near sea and the boat. main() gives each pixel's choice.
// Outputs: the layer (rgb premultiplied radiance, a transmittance) and aux = (cloud distance,
// clipped scene distance, how much of the value was marched at the pixel (1) rather than filled
// (0), 0).
// Failure cases guarded: a never-marched cloud distance (0) counts as far; the projection's
// w ≤ 0 (behind the last camera) and a point off the last frame by more than half a pixel are
// rejected; taps off the image are clamped; grid points whose pixel is off the image move inside.
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

const float RESOLVE_MIN_FORWARD_COS = 1.0e-6;  // floor of cos(ray, camera forward)
const float RESOLVE_NO_DELTA = 1.0e38;         // m, a depth difference larger than any
const float RESOLVE_MIN_WEIGHT = 1.0e-6;       // bilinear weight below which no tap agreed
const float RESOLVE_TIE_BREAK = 1.0e-3;        // m per unit weight: ties go to the nearer tap
const float RESOLVE_MIN_W = 1.0e-30;           // floor of clip w before the divide
const float RESOLVE_NDC_HALF = 0.5;            // uv = ndc · ½ + ½
const float RESOLVE_EDGE_SLACK = 0.5;          // pixels a reprojected point may lie off the frame

// The distance in metres along the unit ray dir to the opaque scene at pixel p, from the window
// depth (the scene's perspective projection, uCamNear–uCamFar), clipped at uFarCloud: two rays
// past the layer's far reach (the sky, the far sea at the horizon) see the same nothing, so
// AmortiseDepthAgree compares clipped distances. No depth, or depth 1 (nothing drawn), gives
// uFarCloud; a ray at right angles to the forward axis is floored at RESOLVE_MIN_FORWARD_COS.
float SceneDistance(ivec2 p, vec3 dir) {
    if (!uHasSceneDepth) return uFarCloud;
    float depth = texelFetch(uSceneDepth, p, 0).r;
    if (depth >= 1.0) return uFarCloud;
    float z = depth * 2.0 - 1.0;
    float viewZ = 2.0 * uCamNear * uCamFar / (uCamFar + uCamNear - z * (uCamFar - uCamNear));
    return min(viewZ / max(dot(dir, uCamForward), RESOLVE_MIN_FORWARD_COS), uFarCloud);
}

// The grid point (texel) of corner (dx, dy) ∈ {0, 1}² of the grid cell around the pixel p, and
// its bilinear weight in [0, 1]. Failure cases: taps off the grid are clamped to it, and a grid
// point whose full-resolution pixel lies off the image (the last row or column when the size is
// not a multiple of B) is moved back to the last one inside.
ivec2 GridTap(ivec2 p, int dx, int dy, out float weight) {
    int b = max(uAmortiseBlock, 1);
    ivec2 gridSize = textureSize(uFresh, 0);
    ivec2 lastInside = max(ivec2(uAmortiseFullSize) - 1 - uAmortiseSub, ivec2(0))
                       >> uAmortiseShift;
    vec2 g = vec2(p - uAmortiseSub) / float(b);
    ivec2 g0 = ivec2(floor(g));
    vec2 f = g - vec2(g0);
    weight = (dx == 1 ? f.x : 1.0 - f.x) * (dy == 1 ? f.y : 1.0 - f.y);
    return min(clamp(g0 + ivec2(dx, dy), ivec2(0), gridSize - 1), lastInside);
}

#if AMORTISE_PATH == 0
// Path 0's fill (twin: app.sim.amortise.fill): the depth-aware bilinear interpolation of the
// fresh grid at p, whose clipped scene distance is dist (metres): the 4 nearest grid points'
// marches with bilinear weights, those whose scene distance disagrees with dist dropped, so the
// clouds do not bleed over a mast or across the horizon. Failure case: none agrees (total weight
// below RESOLVE_MIN_WEIGHT): the march of the point of nearest distance. cloudDist in metres.
void AmortiseFill(ivec2 p, float dist, out vec4 layer, out float cloudDist) {
    vec4 sum = vec4(0.0);
    float sumDist = 0.0, weight = 0.0;
    vec4 best = vec4(0.0, 0.0, 0.0, 1.0);
    float bestDist = AMORTISE_FAR, bestDelta = RESOLVE_NO_DELTA;
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
    if (weight > RESOLVE_MIN_WEIGHT) {
        layer = sum / weight;
        cloudDist = sumDist / weight;
    } else {
        layer = best;
        cloudDist = bestDist;
    }
}
#else
// Paths 1 and 2's fallback (twin: app.sim.amortise.fill_nearest): of the 4 fresh grid points
// around p, the one whose clipped scene distance is closest to dist (metres); a tie goes to the
// nearer point (the larger bilinear weight, by RESOLVE_TIE_BREAK). cloudDist in metres.
void AmortiseFillNearest(ivec2 p, float dist, out vec4 layer, out float cloudDist) {
    ivec2 best = ivec2(0);
    float bestDelta = RESOLVE_NO_DELTA;
    cloudDist = AMORTISE_FAR;
    for (int dy = 0; dy <= 1; ++dy) {
        for (int dx = 0; dx <= 1; ++dx) {
            float w;
            ivec2 t = GridTap(p, dx, dy, w);
            vec2 aux = texelFetch(uFreshAux, t, 0).xy;
            float delta = abs(min(aux.y, uFarCloud) - dist) - RESOLVE_TIE_BREAK * w;
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

// The resolve at pixel p, in this order:
// 1. near cut: the opaque scene is nearer than the layer can be (uNearCloud: the camera's
//    distance to the cloud container): exactly no cloud, (0, 0, 0, 1), so the boat, its mast
//    and the near sea never take a cloud from a neighbour;
// 2. marched this frame (p = t·B + sub): p's own fresh march;
// 3. otherwise, by AMORTISE_PATH:
//    0 (reset: no history): AmortiseFill;
//    1 (still: camera and field where they were): p's own history texel, bit for bit, if its
//      scene distance agrees with p's; else (disocclusion) AmortiseFillNearest;
//    2 (moving): reprojection. The point at p's last cloud distance (the history's, at p) is
//      moved back by the field's shift since the last frame (the wind, uFieldShift) and
//      projected with the last camera (camera-relative: uCameraDelta = this camera − the last).
//      The history is read there bilinearly if the bilinear scene distance equals the nearest
//      texel's (the four texels are one surface), else at the nearest texel, and kept if that
//      texel's scene distance agrees with p's. Else (disocclusion, off the last frame by more
//      than RESOLVE_EDGE_SLACK, or behind its camera) the history at p itself, if p shows an
//      opaque surface within the layer's reach (uFarCloud) whose distance agrees with its
//      texel's (an object that moved with the view, such as a boat the camera follows: no
//      neighbour's cloud bleeds onto it); else AmortiseFillNearest.
#ifdef AMORTISE_NEAR
// 1. nothing between the camera and the opaque scene: the near cut's pass writes these pixels
// (and, through the pass's depth, marks them); it discards the others, which the resolve
// proper writes.
void main() {
    ivec2 p = ivec2(gl_FragCoord.xy);
    float dist = SceneDistance(p, CameraRayDirection(vUV));
    if (dist >= uNearCloud) discard;
    outLayer = vec4(0.0, 0.0, 0.0, 1.0);
    outAux = vec4(AMORTISE_FAR, dist, 1.0, 0.0);
}
#else
void main() {
    ivec2 p = ivec2(gl_FragCoord.xy);
    vec3 dir = CameraRayDirection(vUV);
    float dist = SceneDistance(p, dir);
    // 1. the near cut, when its own pass did not write these pixels (the depth test then skips
    // them here): a frame with no surface before the volumes
    if (dist < uNearCloud) {
        outLayer = vec4(0.0, 0.0, 0.0, 1.0);
        outAux = vec4(AMORTISE_FAR, dist, 1.0, 0.0);
        return;
    }
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
    vec2 uv = clip.xy / max(clip.w, RESOLVE_MIN_W) * RESOLVE_NDC_HALF + RESOLVE_NDC_HALF;
    vec2 xy = uv * uAmortiseFullSize;
    ivec2 q = clamp(ivec2(floor(xy)), ivec2(0), ivec2(uAmortiseFullSize) - 1);
    aux = texelFetch(uHistoryAux, q, 0);
    float mixed = texture(uHistoryAux, uv).y;  // one surface under the 4 texels: no edge
    layer = AmortiseDepthAgree(mixed, aux.y) ? texture(uHistory, uv)
                                             : texelFetch(uHistory, q, 0);
    kept = clip.w > 0.0 && all(greaterThanEqual(xy, vec2(-RESOLVE_EDGE_SLACK)))
        && all(lessThanEqual(xy, uAmortiseFullSize + RESOLVE_EDGE_SLACK))
        && AmortiseDepthAgree(dist, aux.y);
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
    if (all(greaterThanEqual(g, ivec2(0))) && all(equal(gt << uAmortiseShift, g))) {
        // 2. marched now
        outLayer = texelFetch(uFresh, gt, 0);
        outAux = vec4(texelFetch(uFreshAux, gt, 0).x, dist, 1.0, 0.0);
    } else if (kept) {  // 3. the history
        outLayer = layer;
        outAux = vec4(aux.x, dist, aux.z, 0.0);
    } else {  // 3. filled from this frame's marches; only here, so that a block of pixels that
        // all keep their history (a still view, most of a slow pan) skips the fill's taps
        vec4 filled;
        float filledDist;
#if AMORTISE_PATH == 0
        AmortiseFill(p, dist, filled, filledDist);
#else
        AmortiseFillNearest(p, dist, filled, filledDist);
#endif
        outLayer = filled;
        outAux = vec4(filledDist, dist, 0.0, 0.0);
    }
}
#endif
