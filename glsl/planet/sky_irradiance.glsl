// =============================================================================================
// The sky's light on the planet's surfaces (beyond the thesis): the ambient term of the ground
// and the meshes. The thesis's ambient is k_a × the texture colour (spec/002 §3.3; planet.ambient
// = constant, the default); planet.ambient = sky replaces it by albedo · k_d · E(n) / lightSun,
// with E(n) = ∫ L_sky(ω) max(n·ω, 0) dω the irradiance the single-scattering sky gives a surface
// of normal n. The CPU tabulates E / lightSun over the normal's directions
// (app/sim/atmosphere.py, sky_irradiance_table: a 32 × 17 RGB32F table, columns = azimuth from
// −z toward +x, rows = polar angle from +y with the poles on the first and last rows), rebuilt
// when the sun or the model changes; here one bilinear read (SkyIrradiance) gives it.
// Equations: none of the thesis's (its ambient is §3.3's constant).
// Failure cases guarded: the azimuth of a vertical normal is undefined (atan(0, 0) is 0 here
// and every column of a pole row holds the same value); n.y outside [−1, 1] (clamped acos).
// =============================================================================================
uniform sampler2D uSkyIrradiance;   // RGB32F: E(n) / lightSun, LINEAR, u repeats, v clamps
uniform bool uSkyAmbient;           // true: the sky's irradiance; false: k_a × albedo (the thesis)

vec2 SkyIrradianceUv(vec3 n) {
    float h = float(textureSize(uSkyIrradiance, 0).y);
    float phi = atan(n.x, -n.z);                      // −π … π; u repeats
    float theta = acos(ClampCosine(n.y));
    return vec2(phi / TWO_PI, (0.5 + theta / PI * (h - 1.0)) / h);
}

// E(n) / lightSun: the sky's irradiance on a surface of unit normal n per unit sun.
vec3 SkyIrradiance(vec3 n) { return texture(uSkyIrradiance, SkyIrradianceUv(n)).rgb; }

// The ambient term of a surface of albedo a and normal n (uKa, uKd: the Phong factors).
vec3 AmbientLight(vec3 albedo, vec3 n, float ka, float kd) {
    return uSkyAmbient ? albedo * kd * SkyIrradiance(n) : albedo * ka;
}
