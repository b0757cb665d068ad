// The optical-depth lookup table, GPU side. Its numpy twin is app/sim/atmosphere.py
// (OpticalDepthLut, lut_uv), where the parametrisation is explained; tests compile this file
// and compare it with the twin.
uniform sampler2D uOpticalDepthLut;   // RGB32F, LINEAR, CLAMP_TO_EDGE: Chapman ratios (C_R, C_M)
                                      // and the ozone density integral / 15 km

// ---- Optical-depth LUT ("Chapman function", spec/002 §1.8) — twin of app/sim/atmosphere.py --
// Needs uBottomRadius, uTopRadius, uHRayleigh, uHMie, uP0 (model.glsl) and uOpticalDepthLut.
// Texel = density integral to the top / (H · exp(−h_low / H)), h_low = lowest altitude on the
// ray. Rows = height (v): x_h = ρ / H_top; columns = cos Φ (u): x_Φ = (d_max − d)/(d_max − d_min)
// (Bruneton 2017 with u reversed); both mapped to texel centres. Only rays that miss the ground.
const float OPTICAL_DEPTH_GROUND = 1.0e12;   // density integral for sun rays that hit the planet

// True where the ray from height h at cos Φ to the local vertical hits the planet (tangent
// included): cos Φ < 0 and r² cos²Φ ≥ r² − R² = h (2R + h).
bool SunRayHitsGround(float h, float cosPhi) {
    h = max(h, 0.0);
    float r = uBottomRadius + h;
    return cosPhi < 0.0 && r * r * cosPhi * cosPhi >= h * (2.0 * uBottomRadius + h);
}

// Texture coordinates of the table for height h (m) and cos Φ of the ray to the local vertical,
// as described above (twin: lut_uv). h is clamped into the atmosphere, cos Φ into [−1, 1], both
// coordinates into [0, 1]; the caller tests SunRayHitsGround first (those rays are not stored).
vec2 OpticalDepthLutUv(float h, float cosPhi) {
    float R = uBottomRadius;
    float top = uTopRadius - uBottomRadius;
    h = clamp(h, 0.0, top);
    float mu = clamp(cosPhi, -1.0, 1.0);
    float r = R + h;
    float Htop = sqrt(top * (2.0 * R + top));           // sea-level horizontal ray to the top
    float rho = sqrt(h * (2.0 * R + h));                // distance to the horizon
    float k = (top - h) * (2.0 * R + top + h);          // R_top² − r²
    float sq = sqrt(r * r * mu * mu + k);
    float d = mu > 0.0 ? k / (r * mu + sq) : sq - r * mu;   // distance to the top along the ray
    float dMin = top - h;
    float dMax = rho + Htop;
    float xPhi = clamp((dMax - d) / (dMax - dMin), 0.0, 1.0);
    float xH = clamp(rho / Htop, 0.0, 1.0);
    vec2 size = vec2(textureSize(uOpticalDepthLut, 0));
    return (0.5 + vec2(xPhi, xH) * (size - 1.0)) / size;
}

// Lowest altitude between the point and the top: h looking up, the perigee altitude looking down.
float OpticalDepthLowestHeight(float h, float cosPhi) {
    h = clamp(h, 0.0, uTopRadius - uBottomRadius);
    if (cosPhi >= 0.0) return h;
    float R = uBottomRadius;
    float r = R + h;
    float k = max(h * (2.0 * R + h) - r * r * cosPhi * cosPhi, 0.0);   // r_p² − R²
    return k / (sqrt(R * R + k) + R);
}

// Density integrals (P0·D_R, P0·D_M, D_O) in m from height h toward the sun at cos Φ to the top
// of the atmosphere, ready for TransmittanceFromDepths (the ozone layer's D_O has no P0);
// OPTICAL_DEPTH_GROUND (no P0) when the planet hides the sun.
vec3 OpticalDepthToSun(float h, float cosPhi) {
    if (SunRayHitsGround(h, cosPhi)) return vec3(OPTICAL_DEPTH_GROUND);
    vec2 H = vec2(uHRayleigh, uHMie);
    vec2 column = H * exp(-OpticalDepthLowestHeight(h, cosPhi) / H);
    vec3 texel = texture(uOpticalDepthLut, OpticalDepthLutUv(h, cosPhi)).rgb;
    return vec3(uP0 * column * texel.rg, 15000.0 * texel.b);   // 15 km: the tent's column
}

