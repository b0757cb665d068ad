#version 330 core
// =============================================================================================
// Temporal reprojection of the cloud layer (beyond the thesis; Schneider 2015, "The real-time
// volumetric cloudscapes of Horizon: Zero Dawn": one pixel of each 4×4 block is marched per
// frame, the other 15 come from the previous frame).
//   * the pixel marched this frame (uSub within its block) takes the fresh sample;
//   * every other pixel is reprojected: its ray meets the cloud container at distance t, the
//     point X = camera + t·dir is projected with the previous frame's view × projection, and the
//     history is read there;
//   * rejection: X behind the previous camera or off its screen, or the opaque scene's distance
//     changed there (disocclusion) → the fresh 4×4-block sample, bilinearly upsampled;
//   * when the camera moved or the wind blows, the history is clamped to the range of the fresh
//     3×3 block neighbourhood, which bounds ghosting; with everything still it is exact already,
//     and clamping would only blur it (the clamp is measured by the bench).
// Without a history (first frame, resize) the caller marches at full resolution instead.
// Failure cases guarded:
//   * a ray parallel to the base plane (|dir.y| < 1e-6) or missing the shell, or a camera
//     inside / above the layer: a nominal 5 km entry distance (inside the shell: the far root,
//     at least 1 m) — the reprojection depth is then only approximate;
//   * reprojected point behind the previous camera (clip.w ≤ 0) or off its screen, and
//     disocclusion (scene distance changed by more than 5 % + 1 m): the fresh upsampled sample;
//   * sky in both frames (distance 1e30) is not a disocclusion; dot(dir, forward) is floored at
//     1e-4 in the depth-to-distance conversion.
// Remaining: the history is reprojected at the container entry, so cloud detail deep in the
// layer smears slightly under fast camera motion (the clamp bounds it).
// =============================================================================================
#include "camera.glsl"

in vec2 vUV;
layout(location = 0) out vec4 outLayer;      // rgb premultiplied cloud radiance, a = transmittance
layout(location = 1) out vec4 outSceneDist;  // r = opaque-scene distance of this pixel (for next frame)

uniform sampler2D uFresh;         // this frame's samples, one per 4×4 block
uniform sampler2D uHistory;       // last frame's resolved layer
uniform sampler2D uHistoryDist;   // last frame's opaque-scene distances
uniform sampler2D uSceneDepth;    // this frame's window depth
uniform bool uHasSceneDepth;
uniform float uCamNear;
uniform float uCamFar;
uniform ivec2 uSub;               // the pixel of each block marched this frame
uniform bool uFullFresh;          // uFresh is a full-size march (no history yet): copy it
uniform bool uClampHistory;       // the camera moved or the clouds move: clamp the history
uniform mat4 uPrevViewProj;       // previous frame: projection × view (world space)
uniform int uContainer;           // 0 box, 1 spherical shell
uniform float uBaseHeight;
uniform float uPlanetRadius;

float SceneDistance(vec2 uv, vec3 dir) {
    if (!uHasSceneDepth) return 1.0e30;
    float d = texture(uSceneDepth, uv).r;
    if (d >= 1.0) return 1.0e30;
    float z = d * 2.0 - 1.0;
    float viewZ = 2.0 * uCamNear * uCamFar / (uCamFar + uCamNear - z * (uCamFar - uCamNear));
    return viewZ / max(dot(dir, uCamForward), 1.0e-4);
}

// Where the ray first meets the container (or a far point when it starts inside or misses).
float ContainerEntry(vec3 dir) {
    if (uContainer == 0) {  // the layer's base plane (inside or above it: a nominal 5 km)
        float tBase = (uBaseHeight - uCameraPos.y) / (abs(dir.y) > 1.0e-6 ? dir.y : 1.0e-6);
        return tBase > 0.0 ? tBase : 5000.0;
    }
    vec3 c = vec3(0.0, -uPlanetRadius, 0.0);
    vec3 oc = uCameraPos - c;
    float r = uPlanetRadius + uBaseHeight;
    float b = dot(oc, dir);
    float h = b * b - (dot(oc, oc) - r * r);
    if (h < 0.0) return 5000.0;
    float t = -b + sqrt(h);  // from below (inside the sphere): the far root is the way out
    float tn = -b - sqrt(h);
    return tn > 0.0 ? tn : max(t, 1.0);
}

void main() {
    ivec2 p = ivec2(gl_FragCoord.xy);
    ivec2 block = p / 4;
    vec4 fresh = texelFetch(uFresh, block, 0);
    vec3 dir = CameraRayDirection(vUV);
    float sceneDist = SceneDistance(vUV, dir);
    outSceneDist = vec4(sceneDist, 0.0, 0.0, 1.0);
    if (uFullFresh) {
        outLayer = texelFetch(uFresh, p, 0);
        return;
    }
    if (all(equal(p - block * 4, uSub))) {
        outLayer = fresh;
        return;
    }
    vec4 upsampled = texture(uFresh, vUV);
    float t = min(ContainerEntry(dir), sceneDist);
    vec3 X = uCameraPos + dir * t;
    vec4 clip = uPrevViewProj * vec4(X, 1.0);
    if (clip.w <= 0.0) { outLayer = upsampled; return; }
    vec2 uvPrev = clip.xy / clip.w * 0.5 + 0.5;
    if (any(lessThan(uvPrev, vec2(0.0))) || any(greaterThan(uvPrev, vec2(1.0)))) { outLayer = upsampled; return; }
    float prevDist = texture(uHistoryDist, uvPrev).r;
    bool bothSky = prevDist > 1.0e29 && sceneDist > 1.0e29;
    if (!bothSky && abs(prevDist - sceneDist) > 0.05 * min(prevDist, sceneDist) + 1.0) {
        outLayer = upsampled;  // disocclusion: the opaque scene changed under this pixel
        return;
    }
    vec4 history = texture(uHistory, uvPrev);
    if (!uClampHistory) {
        outLayer = history;
        return;
    }
    ivec2 size = textureSize(uFresh, 0);
    vec4 lo = vec4(1.0e30), hi = vec4(-1.0e30);
    for (int y = -1; y <= 1; ++y) {
        for (int x = -1; x <= 1; ++x) {
            vec4 s = texelFetch(uFresh, clamp(block + ivec2(x, y), ivec2(0), size - 1), 0);
            lo = min(lo, s);
            hi = max(hi, s);
        }
    }
    outLayer = clamp(history, lo, hi);
}
