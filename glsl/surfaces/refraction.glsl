// =============================================================================================
// Refraction through the surfaces lab's dielectrics (spec/003 §2.7, the thesis's §5.3): the
// distortion texture as a bump map, the refraction's blur by sample LOD ("Transparency"), the
// final lerp between refraction and reflection, and — beyond the thesis, which refracts once at
// the front face — the two-interface sphere (entry and exit). An include of functions; numpy
// twin app/sim/optics.py (one function each). Snell and Fresnel are glsl/common/fresnel.glsl.
//   n' = normalize(n + s·(d.x·t + d.y·b))     the distortion (d = 2·tex.rg − 1, already unpacked)
//                                             as a bump map; s = Distortion · Smoothness: the
//                                             thesis says Smoothness "scales the distortion",
//                                             read literally as a factor (DistortionStrength)
//   lod = (1 − Transparency)·(mipCount − 1)   Transparency 1: the sharp level 0; 0: the
//                                             coarsest level (most opaque look); Fig. 68's 0.569
//                                             gives 0.431 of the chain
//   colour = lerp(refracted, reflected, R)    the thesis's final lerp, R the Fresnel reflectance
// Failure cases guarded: the distortion strength, Transparency and R clamped (strength ≥ 0,
// [0, 1]); mipCount < 1 treated as 1 (lod 0); the sphere's chord length kept ≥ 0 (a point a
// little off the surface from rounding); total internal reflection inside the sphere returns
// the internally reflected direction with tir = true (no NaN: fresnel.glsl's RefractDirection).
// =============================================================================================
#include "fresnel.glsl"

// The thesis's Smoothness scales the distortion: strength = amount · smoothness, ≥ 0.
float DistortionStrength(float amount, float smoothness) {
    return max(amount * clamp(smoothness, 0.0, 1.0), 0.0);
}

// Perturb the unit normal n by the distortion texture's xy (in [−1, 1]) along the tangent
// frame (t, b), scaled by strength: a bump map of the refraction's normal.
vec3 DistortNormal(vec3 n, vec3 tangent, vec3 bitangent, vec2 distortionXY, float strength) {
    float s = max(strength, 0.0);
    return normalize(n + s * (distortionXY.x * tangent + distortionXY.y * bitangent));
}

// The refraction's sample LOD from the thesis's Transparency (lower = more opaque, blurrier),
// mipCount the number of levels of the refracted cubemap: (1 − T)·(mipCount − 1).
float RefractionLod(float transparency, float mipCount) {
    return (1.0 - clamp(transparency, 0.0, 1.0)) * max(mipCount - 1.0, 0.0);
}

// The final colour: lerp(refracted, reflected, reflectance), reflectance clamped into [0, 1].
vec3 RefractReflectMix(vec3 refracted, vec3 reflected, float reflectance) {
    return mix(refracted, reflected, clamp(reflectance, 0.0, 1.0));
}

// Beyond the thesis: the exit direction of the ray v (unit, toward the sphere) that enters the
// sphere (centre, radius) at its surface point p, refracted at entry (η = n1/n2, n1 outside)
// and at exit (1/η). tir = true when either interface totally reflects: at entry the reflected
// direction is returned, inside the internally reflected one (the ray stays in the sphere).
vec3 RefractThroughSphere(vec3 p, vec3 v, vec3 centre, float radius, float eta, out bool tir) {
    vec3 n = normalize(p - centre);
    vec3 d = RefractDirection(v, n, eta, tir);
    if (tir) return d;
    vec3 o = p - centre;                                      // far root of |o + t·d| = radius
    float b = dot(o, d);
    float t = max(-b + sqrt(max(b * b - (dot(o, o) - radius * radius), 0.0)), 0.0);
    vec3 q = p + t * d;
    vec3 nIn = normalize(centre - q);                         // facing d's origin (inside)
    return RefractDirection(d, nIn, 1.0 / eta, tir);
}

// One interface (the thesis: the front face only) or two (RefractThroughSphere).
vec3 RefractSphere(int interfaces, vec3 p, vec3 v, vec3 centre, float radius, float eta,
                   out bool tir) {
    if (interfaces <= 1) return RefractDirection(v, normalize(p - centre), eta, tir);
    return RefractThroughSphere(p, v, centre, radius, eta, tir);
}
