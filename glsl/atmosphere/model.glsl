// =============================================================================================
// The physical model shared by every atmosphere method — atmospheric-scattering thesis
// (spec/002 §1, constants §7) — in camera-relative coordinates.
//
//   density        ρ_x(h) = P0 · exp(−h / H_x),  H_R = 7994 m, H_M = 1200 m                 (§1.3)
//   extinction     β^ext_R = β^scatt_R = (5.8, 13.5, 33.1)·10⁻⁶ /m,
//                  β^ext_M = β^scatt_M + β^abs_M = 1.1 · 2·10⁻⁵ /m                           (§1.3)
//   transmittance  T = exp(−(β^ext_R τ_R + β^ext_M τ_M))   — e^(−τ), not ×τ (erratum of §1.4)
//   phases         Rayleigh 3/(16π)(1 + μ²); Mie: Cornette–Shanks, |G| < 1
//                  (§1.2; common/phase.glsl)
//   ozone          beyond the thesis (uOzoneAbsorption = 0 there): absorption only, a tent of
//                  relative density 0 below 10 km, 1 at 25 km, 0 from 40 km (Bruneton 2017,
//                  Hillaire 2020), σ_a = atmosphere.ozone · (0.650, 1.881, 0.085)·10⁻⁶ /m at its
//                  peak; no P0. Density integrals are then vec3 (R, M, O):
//                  T = exp(−(β^ext_R τ_R + β^ext_M τ_M + σ_a τ_O))
//
// Coordinates: metres, world axes, the camera at the origin; the planet centre is uEarthCenter
// (= C_earth − camera, computed in double precision on the CPU). Float32 at planet scale
// cannot hold absolute positions to better than ~0.5 m, so heights along a view ray use the
// stable form r(t)² = t² + 2 r_c μ t + r_c² from the camera's radius r_c (exact, from the CPU)
// and the cosine μ between the ray and the local vertical.
// Failure cases guarded: G → ±1 (validated on the CPU, clamped here), rays that miss a sphere
// (negative discriminant → no segment), sqrt of tiny negatives (SafeSqrt).
// =============================================================================================
#include "math.glsl"
#include "phase.glsl"
#include "intersect.glsl"

uniform vec3 uEarthCenter;      // planet centre relative to the camera (m)
uniform float uCameraRadius;    // |camera − C_earth| (m), exact from the CPU
uniform float uBottomRadius;    // 6 360 000 m
uniform float uTopRadius;       // bottom + atmosphere height (60 km by default)
uniform vec3 uBetaRayleigh;     // β^scatt_R = β^ext_R (1/m)
uniform vec3 uBetaMieScatter;   // β^scatt_M (1/m)
uniform vec3 uBetaMieExt;       // β^ext_M = 1.1 β^scatt_M (1/m)
uniform float uHRayleigh;       // 7994 m
uniform float uHMie;            // 1200 m
uniform float uP0;              // density scale at sea level (1)
uniform float uMieG;            // Cornette–Shanks asymmetry, |G| < 1
uniform float uSunIntensity;    // "lightSun" (30)
uniform vec3 uSunDir;           // unit vector toward the sun
uniform vec3 uOzoneAbsorption;  // ozone's σ_a at the tent's peak (1/m); 0: no ozone (the thesis)

const float OZONE_BOTTOM = 10000.0;   // m: the tent starts (twin: app/sim/atmosphere.py)
const float OZONE_PEAK = 25000.0;     // m: relative density 1
const float OZONE_TOP = 40000.0;      // m: back to 0

// The view segment clipped to the atmosphere (spec/002 §2.4 item 2, §9 criterion 6):
// returns (t0, t1) with t0 ≤ t1, or (-1, -1) when it does not cross the atmosphere.
vec2 AtmosphereSegment(vec3 dir, float maxDist) {
    vec2 top;
    if (!RaySphereIntersect(vec3(0.0), dir, uEarthCenter, uTopRadius, top) || top.y <= 0.0) {
        return vec2(-1.0);
    }
    float t0 = max(top.x, 0.0);
    float t1 = min(top.y, maxDist);
    if (t1 <= t0) return vec2(-1.0);
    return vec2(t0, t1);
}

// Distance to the ground along dir, or a huge value when the ray misses the planet.
float GroundDistance(vec3 dir) {
    vec2 g;
    return RaySphereIntersect(vec3(0.0), dir, uEarthCenter, uBottomRadius, g) && g.x > 0.0
        ? g.x : 1.0e30;
}

// Height above sea level at distance t along a view ray whose cosine with the camera's local
// vertical is mu (stable at planet scale).
float HeightAlongRay(float t, float mu) {
    float r = SafeSqrt(t * t + 2.0 * uCameraRadius * mu * t + uCameraRadius * uCameraRadius);
    return r - uBottomRadius;
}

vec3 CameraUp() { return normalize(-uEarthCenter); }

vec2 DensityRM(float h) { return uP0 * exp(-max(h, 0.0) / vec2(uHRayleigh, uHMie)); }

// The ozone layer's relative density: a tent 10–25–40 km (0 outside).
float DensityOzone(float h) {
    return max(1.0 - abs(h - OZONE_PEAK) / (OZONE_PEAK - OZONE_BOTTOM), 0.0);
}

// (ρ_R, ρ_M, ρ_O): the two scattering densities with P0 and the ozone density (no P0).
vec3 DensityRMO(float h) { return vec3(DensityRM(h), DensityOzone(h)); }

vec3 TransmittanceFromDepths(vec2 depthRM) {
    return exp(-(uBetaRayleigh * depthRM.x + uBetaMieExt * depthRM.y));
}

// The same with the ozone density integral as a third component.
vec3 TransmittanceFromDepths(vec3 depthRMO) {
    return exp(-(uBetaRayleigh * depthRMO.x + uBetaMieExt * depthRMO.y
                 + uOzoneAbsorption * depthRMO.z));
}
