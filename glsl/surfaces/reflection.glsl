// Reflection probes and metallic/dielectric of the surfaces lab (spec/003 §2.5 reflections,
// spec/003 §2.6 metallic vs dielectric), and the split-sum prefiltered GGX reference (Karis
// 2013). An include of functions; numpy twin app/sim/reflections.py (one function each).
// Failure cases guarded: a direction component near 0 gives that axis an infinite box
// distance (no division by 0); a point outside the probe box gets d = max(d, 0) (never a
// negative stretch); a segment that misses the sphere (point outside it, b² − 4ac < 0) falls
// back to the plain direction; the approximation's h is clamped at 0 and x to [0, 1]; the LUT
// coordinates are clamped to [0, 1]; mip levels are clamped to the cube's last level.
#ifndef SURFACES_REFLECTION_GLSL
#define SURFACES_REFLECTION_GLSL

#define REFLECTION_NONE 0
#define REFLECTION_CUBE 1
#define REFLECTION_BOX 2
#define REFLECTION_APPROXIMATION 3
#define REFLECTION_PERFECT 4

//: Unity's UNITY_SPECCUBE_LOD_STEPS (mip levels spanned by perceptual roughness 0 → 1)
#define PROBE_LOD_STEPS 6.0
//: Unity's LUT_RANGE: the NHxRoughness texture stores intensity / 16
#define NHX_LUT_RANGE 16.0
#include "math.glsl"  // PI

//: the smallest |dir_i| divided by; a smaller one gives its axis no face (distance FAR_AWAY)
const float MIN_DIR = 1e-8;
//: m: "no face on this axis", larger than any box distance
const float FAR_AWAY = 1e30;
//: m: the smallest box side divided by (a flat box)
const float MIN_BOX_SIDE = 1e-6;
//: Unity's perceptualRoughnessToMipmapLevel: level = r·(MIP_CURVE − MIP_CURVE_SLOPE·r)·steps
const float MIP_CURVE = 1.7;
const float MIP_CURVE_SLOPE = 0.7;
//: 2⁻³²: a 32-bit radical inverse as a fraction in [0, 1)
const float INV_2_POW_32 = 2.3283064365386963e-10;
//: |n.z| above which the tangent frame is built from +x instead of +z (cross product near 0)
const float NEAR_POLE = 0.999;

// Distance along dir from p to each face plane it heads for: d_i = (face_i − p_i) / dir_i —
// with |dir| = 1, dir_i is cos(r, axis i), so this is spec/003 eq. 5.2 (x) and
// spec/003 eq. 5.3 (y), plus the same for z. p, boxMin, boxMax in metres (world); dir unit;
// result in metres. Failure case: a component of dir near 0 would divide by 0; that axis gets
// the distance FAR_AWAY instead, so it never wins the minimum.
vec3 BoxDistances(vec3 p, vec3 dir, vec3 boxMin, vec3 boxMax) {
    vec3 face = mix(boxMin, boxMax, step(0.0, dir));
    vec3 safe = mix(vec3(MIN_DIR), dir, step(MIN_DIR, abs(dir)));
    vec3 d = (face - p) / safe;
    return mix(vec3(FAR_AWAY), d, step(MIN_DIR, abs(dir)));
}

// d = min(d_x, d_y, d_z): spec/003 eq. 5.4 in three dimensions (criterion 21), in metres.
// Failure case: a point outside the box gets d = max(d, 0), never a negative stretch.
float BoxDistance(vec3 p, vec3 dir, vec3 boxMin, vec3 boxMax) {
    vec3 d = BoxDistances(p, dir, boxMin, boxMax);
    return max(min(d.x, min(d.y, d.z)), 0.0);
}

// The quadratic stretch f(x, h) = 4hx(1 − x): spec/003 eq. 5.9 (f(0) = f(1) = 0, f(½) = h).
// x: where the hit lies across the face [0, 1] (clamped); h and the result in metres.
float QuadraticStretch(float x, float h) {
    x = clamp(x, 0.0, 1.0);
    return 4.0 * h * x * (1.0 - x);
}

// t where the segment P(t) = (p1 − p0)t + p0 leaves the sphere |X − C| = r:
// a = |p1 − p0|², b = 2(p1 − p0)·(p0 − C), c = |p0 − C|² − r², t = (−b + √(b² − 4ac)) / 2a;
// −1 when the segment's line misses the sphere (b² − 4ac < 0, the point outside it) or the
// segment has no length. Points and radius in metres; t along the segment (1 at p1).
float SphereSegmentT(vec3 p0, vec3 p1, vec3 centre, float radius) {
    vec3 seg = p1 - p0;                                  // spec/003 eq. 5.11
    vec3 oc = p0 - centre;
    float a = dot(seg, seg);                             // spec/003 eq. 5.14
    float b = 2.0 * dot(seg, oc);                        // spec/003 eq. 5.15
    float c = dot(oc, oc) - radius * radius;             // spec/003 eq. 5.16
    float disc = b * b - 4.0 * a * c;                    // from spec/003 eq. 5.10
    if (disc < 0.0 || a <= 0.0) return -1.0;
    return (-b + sqrt(disc)) / (2.0 * a);                // spec/003 eq. 5.17
}

// The direction to sample the probe's cubemap with, for the reflected direction dir (unit)
// at worldPos (m). mode: 0 none and 1 cube return dir; 2 box projection r' = d·r + (P − C)
// (spec/003 eq. 5.1, d of spec/003 eq. 5.4); 3 the quadratic-stretch approximation of the
// sphere of radius sphereRadius (m) around the probe: d + f(x, h) with h = d_cmax − d_cmin
// (sphere radius minus the probe's distance to the intersected face) and f averaged over the
// face's two in-face axes (x = where the box hit A lies across the face, 0 at one edge, 1 at
// the other); 4 the perfect sphere: P(t) − C for the segment from P of length 2r + |P − C|
// (t ∈ [0, 1]). The result is not normalised (a cubemap lookup needs no unit vector).
// Failure cases: a segment that misses the sphere falls back to the plain direction; h is
// clamped at 0; a flat box side is raised to MIN_BOX_SIDE before dividing.
vec3 ComputeReflexDirection(int mode, vec3 worldPos, vec3 dir, vec3 probePos, vec3 boxMin,
                            vec3 boxMax, float sphereRadius) {
    if (mode <= REFLECTION_CUBE) return dir;
    if (mode == REFLECTION_PERFECT) {
        float len = 2.0 * sphereRadius + length(worldPos - probePos);
        vec3 p1 = worldPos + len * dir;
        float t = SphereSegmentT(worldPos, p1, probePos, sphereRadius);
        if (t < 0.0) return dir;
        return worldPos + t * (p1 - worldPos) - probePos;
    }
    vec3 ds = BoxDistances(worldPos, dir, boxMin, boxMax);
    float d = BoxDistance(worldPos, dir, boxMin, boxMax);  // recomputes ds: the compiler shares it
    if (mode == REFLECTION_APPROXIMATION) {
        vec3 hit = worldPos + d * dir;
        vec3 x = clamp((hit - boxMin) / max(boxMax - boxMin, vec3(MIN_BOX_SIDE)), 0.0, 1.0);
        vec3 face = mix(boxMin, boxMax, step(0.0, dir));
        float stretch;
        float h;
        if (ds.x <= ds.y && ds.x <= ds.z) {
            h = max(sphereRadius - abs(face.x - probePos.x), 0.0);
            stretch = 0.5 * (QuadraticStretch(x.y, h) + QuadraticStretch(x.z, h));
        } else if (ds.y <= ds.z) {
            h = max(sphereRadius - abs(face.y - probePos.y), 0.0);
            stretch = 0.5 * (QuadraticStretch(x.x, h) + QuadraticStretch(x.z, h));
        } else {
            h = max(sphereRadius - abs(face.z - probePos.z), 0.0);
            stretch = 0.5 * (QuadraticStretch(x.x, h) + QuadraticStretch(x.y, h));
        }
        d += stretch;
    }
    return d * dir + (worldPos - probePos);              // spec/003 eq. 5.1
}

// weight = 0.25·Smoothness + 0.75·Metallic: spec/003 eq. 5.18 (Table 1: 0, 0.75, 0.25, 1).
// Inputs and result in [0, 1]; the two factors are the equation's own.
float ReflectionWeight(float smoothness, float metallic) {
    return 0.25 * smoothness + 0.75 * metallic;
}

// GetSpecularColorByMetallic: lerp(lightColor, albedo, metallic) (spec/003 §2.6): a metal
// tints its reflection with its albedo, a dielectric keeps the light's colour. Linear RGB.
vec3 SpecularColorByMetallic(vec3 lightColour, vec3 albedo, float metallic) {
    return mix(lightColour, albedo, metallic);
}

// GetSpecularIntensityFromLUT (spec/003 §2.6): Unity's unity_NHxRoughness texture sampled at
// ((n·h)⁴, perceptual roughness) and × 16 (LUT_RANGE). The texture (app.sim.reflections
// .nhx_roughness_lut) holds the normalised Blinn-Phong lobe (n + 2)/(2π)·cos^n ÷ 16.
// Result: the lobe's value (1/sr). Failure case: n·h and the roughness are clamped into
// [0, 1], so the lookup never leaves the texture.
float SpecularIntensityFromLUT(sampler2D nhxLut, float nh, float roughness) {
    float c = clamp(nh, 0.0, 1.0);
    float c2 = c * c;
    vec2 uv = vec2(c2 * c2, clamp(roughness, 0.0, 1.0));
    return texture(nhxLut, uv).r * NHX_LUT_RANGE;
}

// Unity's perceptualRoughnessToMipmapLevel: r = 1 − smoothness, r·(1.7 − 0.7r)·6, at most the
// cube's last level (mipCount − 1; 0 for a cube without mips). Smoothness in [0, 1] (clamped).
float ProbeMipLevel(float smoothness, float mipCount) {
    float r = clamp(1.0 - smoothness, 0.0, 1.0);
    return min(r * (MIP_CURVE - MIP_CURVE_SLOPE * r) * PROBE_LOD_STEPS, max(mipCount - 1.0, 0.0));
}

// UNITY_SAMPLE_TEXCUBE_LOD with the level of ProbeMipLevel: the blur of a rough mirror
// (spec/003 §2.5, Fig. 57). Linear radiance.
vec3 SampleProbe(samplerCube probe, vec3 dir, float smoothness, float mipCount) {
    return textureLod(probe, dir, ProbeMipLevel(smoothness, mipCount)).rgb;
}

// The split-sum reference (Karis 2013 eq. 2): prefiltered radiance at the level of the
// perceptual roughness (level = roughness · (mipCount − 1), one level per roughness step) ×
// (F0·A + B) from the 2D BRDF LUT at (n·v, roughness). Linear radiance; n·v and the
// roughness are clamped into [0, 1].
vec3 PrefilteredSpecular(samplerCube prefiltered, sampler2D brdfLut, vec3 dir, float nv,
                         float roughness, vec3 f0, float mipCount) {
    float r = clamp(roughness, 0.0, 1.0);
    vec3 pre = textureLod(prefiltered, dir, r * max(mipCount - 1.0, 0.0)).rgb;
    vec2 ab = texture(brdfLut, vec2(clamp(nv, 0.0, 1.0), r)).rg;
    return pre * (f0 * ab.x + ab.y);
}

// -- GGX importance sampling (the prefilter and BRDF-LUT passes) -------------------------------
// The i-th of n points of the Hammersley set (radical inverse in base 2), in [0, 1)².
vec2 Hammersley(uint i, uint n) {
    uint b = i;
    b = (b << 16u) | (b >> 16u);
    b = ((b & 0x55555555u) << 1u) | ((b & 0xAAAAAAAAu) >> 1u);
    b = ((b & 0x33333333u) << 2u) | ((b & 0xCCCCCCCCu) >> 2u);
    b = ((b & 0x0F0F0F0Fu) << 4u) | ((b & 0xF0F0F0F0u) >> 4u);
    b = ((b & 0x00FF00FFu) << 8u) | ((b & 0xFF00FF00u) >> 8u);
    return vec2(float(i) / float(n), float(b) * INV_2_POW_32);
}

// A unit half vector drawn from the GGX distribution of α = roughness² around the unit n
// (Karis 2013), for xi in [0, 1)². Failure case: n near ±z would make cross(+z, n) vanish;
// the frame is then built from +x.
vec3 ImportanceSampleGGX(vec2 xi, vec3 n, float alpha) {
    float phi = 2.0 * PI * xi.x;
    float cosTheta = sqrt((1.0 - xi.y) / (1.0 + (alpha * alpha - 1.0) * xi.y));
    float sinTheta = sqrt(max(1.0 - cosTheta * cosTheta, 0.0));
    vec3 h = vec3(sinTheta * cos(phi), sinTheta * sin(phi), cosTheta);
    vec3 up = abs(n.z) < NEAR_POLE ? vec3(0.0, 0.0, 1.0) : vec3(1.0, 0.0, 0.0);
    vec3 tx = normalize(cross(up, n));
    vec3 ty = cross(n, tx);
    return normalize(tx * h.x + ty * h.y + n * h.z);
}

// GGX normal distribution D(n·h) for α (1/sr). α = 0 with n·h = 1 divides 0 by 0: the
// callers never pass α = 0.
float GgxD(float nh, float alpha) {
    float a2 = alpha * alpha;
    float d = nh * nh * (a2 - 1.0) + 1.0;
    return a2 / (PI * d * d);
}

// Smith–Schlick geometry term with k = α/2 (Karis 2013, image-based lighting), in [0, 1].
float SmithGIbl(float nv, float nl, float alpha) {
    float k = alpha * 0.5;
    return (nv / (nv * (1.0 - k) + k)) * (nl / (nl * (1.0 - k) + k));
}

#endif
