// =============================================================================================
// A calm sea plane below a sky — beyond the theses (neither spec/000 §1.7's day–night sky nor
// spec/001 §1.8's Preetham sky has a ground; both clamp the lower hemisphere to the horizon
// colour). Shared by every sky that draws one (glsl/sky/sky_radiance.glsl: SkySea;
// glsl/preetham/preetham.glsl: PreethamSea); each sky supplies what is its own:
//   reflected   its radiance toward SeaReflectionDirection(p, mss) (the caller evaluates it: GLSL
//               has no function arguments), without the sun or moon disk (the glitter is their
//               reflection, spread by the waves)
//   horizon     its radiance at the horizon toward SeaHorizonDirection(p)
//   skyAmbient  (1/π)∫ L cosθ dω of its upper hemisphere (the body's diffuse light)
//   l, E        the main light's direction and radiance (irradiance on a surface facing it)
//
// Radiance of the sea toward the view direction p (p.y < 0, y up, n = up, v = −p):
//   cos θr = min(sqrt((n·v)² + mss), 1)  the incidence the waves leave: facets tilted by the rms
//            slope, so a rough sea's horizon is darker than the sky's (grazing never reaches 90°)
//   F      = F0 + (1 − F0)(1 − cos θr)^5       Schlick 1994's Fresnel, F0 = 0.0204 (n = 1.333)
//   body   = bodyColor · (skyAmbient + E·max(l·n, 0)/π)        upwelling radiance per irradiance/π
//   D(h)   = exp(−tan²θh / mss) / (π·mss·cos⁴θh)               Beckmann, isotropic slope variance
//   G      = min(1, 2(n·h)(n·v)/(v·h), 2(n·h)(n·l)/(v·h))      Cook–Torrance masking
//   glitter = E · F(v·h) · D(n·h) · G / (4 n·v) · glitterFactor
//   sea    = mix(body, reflected, F) + glitter
//   out    = mix(sea, horizon, 1 − exp(−(eyeHeight / n·v) / hazeDistance))   haze over distance
// mss = Cox & Munk 1954's slope variance 0.003 + 0.00512·U for the wind U (the caller's CPU).
//
// Failure cases guarded: n·v and v·h clamped before division (1e-4, 1e-3: the glitter stays
// finite at the horizon, where the haze and F → 1 meet the sky continuously); cos²θh kept above
// 1e-4 in Beckmann; the horizontal direction of a ray straight down kept non-zero (1e-6) before
// normalising; cos θr capped at 1 (mss > 1 would push it past).
// Numpy twin: app/sim/sea_plane.py (one function per GLSL function; tests/gl/test_sea_plane.py).
// =============================================================================================
#include "math.glsl"
#include "fresnel.glsl"

const float SEA_F0 = 0.0204;

// cos θr: the incidence the waves leave toward the sky for the view direction p (p.y < 0).
float SeaRoughIncidence(vec3 p, float mss) {
    float nv = max(-p.y, 1e-4);
    return min(sqrt(nv * nv + mss), 1.0);
}

// The direction the sea reflects toward p comes from: p mirrored, lifted to the incidence θr.
vec3 SeaReflectionDirection(vec3 p, float mss) {
    float nvRough = SeaRoughIncidence(p, mss);
    return normalize(vec3(p.x, 0.0, p.z) * sqrt(1.0 - nvRough * nvRough)
                     / max(length(p.xz), 1e-6) + vec3(0.0, nvRough, 0.0));
}

// The horizon straight beyond p (where the haze fades the sea to).
vec3 SeaHorizonDirection(vec3 p) { return normalize(vec3(p.x, 1e-4, p.z)); }

// Isotropic Beckmann distribution of facet normals for the slope variance mss (= m²).
float SeaBeckmann(float nh, float mss) {
    float c2 = max(nh * nh, 1e-4);
    float tan2 = (1.0 - c2) / c2;
    return exp(-tan2 / mss) / (PI * mss * c2 * c2);
}

// The sea's radiance toward p (p.y < 0); see the header for what each argument is.
vec3 SeaPlaneRadiance(vec3 p, vec3 reflected, vec3 horizon, vec3 skyAmbient, vec3 l, vec3 E,
                      vec3 bodyColor, float mss, float glitterFactor, float eyeHeight,
                      float hazeDistance) {
    float nv = max(-p.y, 1e-4);
    vec3 v = -p;
    float F = SchlickFresnel(SEA_F0, SeaRoughIncidence(p, mss));
    vec3 body = bodyColor * (skyAmbient + E * max(l.y, 0.0) / PI);
    vec3 h = normalize(l + v);
    float nh = max(h.y, 0.0);
    float vh = max(dot(v, h), 1e-3);
    float nl = max(l.y, 0.0);
    float G = min(1.0, min(2.0 * nh * nv / vh, 2.0 * nh * nl / vh));
    vec3 glitter = E * SchlickFresnel(SEA_F0, vh) * SeaBeckmann(nh, mss) * G / (4.0 * nv);
    vec3 sea = mix(body, reflected, F) + glitter * glitterFactor;
    return mix(sea, horizon, 1.0 - exp(-(eyeHeight / nv) / hazeDistance));
}
