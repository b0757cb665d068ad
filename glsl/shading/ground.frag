#version 330 core
// The shading lab's ground (spec/003 §2.1 lighting models, §2.12 toon, §2.8 shadows), program
// ProgramSpec("shading/ground"): ground.vert + this file. A neutral reference under the test
// objects — a checker of 0.5 m squares or a grid of 1 m and 0.25 m lines — lit by the lab's
// own lights and model (lighting.glsl's ShadeSurfaceShadowed: the same toon bands as the
// objects, no specular), the sun's shadow from the shared shadow module (shadow.glsl: the
// objects' shadows on the ground), and a contact shadow under each object: an ambient
// occlusion of its footprint, 1 − k·exp(−d/falloff) outside it (d the distance to the
// footprint's rounded rectangle, uContact), so every object stands on the ground even where
// the sun's shadow falls away from it. Far from the objects the ground fades into the
// background colour (no visible edge).
//
// Interface: uViewProj, uCameraPos, uCameraForward, the lights of lighting.glsl (as
// surface.frag), the sun's shadow uniforms of shadow.glsl; uGroundMode (1 grid, 2 checker),
// uGroundAlbedo (vec2: the light and dark squares), uGroundFade (vec2: fade start, end, metres
// from uGroundCentre), uGroundCentre (xz), uBackground (linear), uContactCount, uContactPos[6]
// (x, z, cos θ, sin θ of the footprint's rotation), uContactSize[6] (half extents x, z),
// uContactStrength, uContactFalloff (metres).
//
// Failure cases guarded: the grid lines and the checker are filtered by their screen footprint
// (fwidth): far away, where a square is smaller than a pixel, they fade to their mean instead of
// aliasing into moiré; a zero falloff or zero-size footprint keeps a finite occlusion; the
// ground seen from below (camera under y = 0) is lit as its upper side, never NaN.
#include "lighting.glsl"
#include "shadow.glsl"

in vec3 vWorldPos;

uniform vec3 uCameraPos;
uniform vec3 uCameraForward;
uniform int uGroundMode;
uniform vec2 uGroundAlbedo;
uniform vec2 uGroundFade;
uniform vec2 uGroundCentre;
uniform vec3 uBackground;
uniform int uContactCount;
uniform vec4 uContactPos[6];
uniform vec2 uContactSize[6];
uniform float uContactStrength;
uniform float uContactFalloff;

out vec4 fragColor;

// A filtered checker of squares of side s: the box-filtered square wave of each axis
// (the integral of the pattern over the pixel's footprint), product-combined.
float Checker(vec2 p, float s) {
    vec2 q = p / s;
    vec2 w = max(fwidth(q), vec2(1e-4));
    // integral of the ±1 square wave: triangle wave
    vec2 i = (abs(fract((q - 0.5 * w) * 0.5) - 0.5) - abs(fract((q + 0.5 * w) * 0.5) - 0.5)) / w;
    return 0.5 - 0.5 * i.x * i.y * 4.0;  // 0 light, 1 dark
}

// Anti-aliased grid lines of spacing s and width px pixels, faded as they shrink below a pixel.
float Grid(vec2 p, float s, float px) {
    vec2 q = p / s;
    vec2 w = max(fwidth(q), vec2(1e-4));
    vec2 d = abs(fract(q - 0.5) - 0.5) / w;
    float line = 1.0 - min(min(d.x, d.y) / px, 1.0);
    float fade = clamp(1.5 - 2.0 * max(w.x, w.y) * 4.0, 0.0, 1.0);
    return line * fade;
}

// The contact shadow under the lab's objects at ground point p (x, z in metres), in [0, 1]:
// the product over up to 6 objects of 1 − strength·exp(−d/falloff), d the distance to the
// object's rotated footprint rectangle (0 inside it). The falloff is floored at 1e-3 m.
float ContactOcclusion(vec2 p) {
    float occ = 1.0;
    int n = clamp(uContactCount, 0, 6);
    float falloff = max(uContactFalloff, 1e-3);
    for (int i = 0; i < 6; ++i) {
        if (i >= n) break;
        vec2 d = p - uContactPos[i].xy;
        vec2 local = vec2(dot(d, uContactPos[i].zw), dot(d, vec2(-uContactPos[i].w,
                                                                  uContactPos[i].z)));
        vec2 q = abs(local) - max(uContactSize[i], vec2(0.0));
        float dist = length(max(q, 0.0)) + min(max(q.x, q.y), 0.0);
        float k = exp(-max(dist, 0.0) / falloff);
        occ *= 1.0 - clamp(uContactStrength, 0.0, 1.0) * k;
    }
    return occ;
}

void main() {
    vec3 p = vWorldPos;
    vec3 n = vec3(0.0, 1.0, 0.0);
    vec3 v = SafeNormalize(uCameraPos - p, n);
    float tone = 0.0;
    if (uGroundMode == 2) tone = Checker(p.xz, 0.5);
    float albedo = mix(uGroundAlbedo.x, uGroundAlbedo.y, tone);
    float line = uGroundMode == 1 ? max(Grid(p.xz, 1.0, 1.2), 0.5 * Grid(p.xz, 0.25, 0.8))
                                  : 0.6 * Grid(p.xz, 1.0, 1.0);
    albedo = mix(albedo, 0.75 * uGroundAlbedo.y, line);
    float viewDepth = dot(p - uCameraPos, uCameraForward);
    float sun = ShadowSun(p, n, viewDepth);
    vec3 colour = ShadeSurfaceShadowed(p, n, v, vec3(albedo), 0.0, 0.0, sun);
    colour *= ContactOcclusion(p.xz);
    float r = length(p.xz - uGroundCentre);
    float fade = smoothstep(uGroundFade.x, max(uGroundFade.y, uGroundFade.x + 1e-3), r);
    fragColor = vec4(mix(max(colour, vec3(0.0)), uBackground, fade), 1.0);
}
