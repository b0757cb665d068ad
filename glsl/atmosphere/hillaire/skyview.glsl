// =============================================================================================
// Method 4 — the sky-view LUT parametrisation (Hillaire 2020 §5.3; 192 × 108 in the paper),
// shared by the LUT pass (skyview_lut.frag) and the lookup (hillaire_lookup.glsl).
//
// The sky seen from the camera depends on the view zenith angle θ and the azimuth φ between the
// view and the sun (the sky is symmetric about the vertical plane through the sun, φ ∈ [0, π]).
// Latitude is mapped non-linearly so texels crowd at the ground horizon, where the sky changes
// fastest (Hillaire §5.3):
//   β     = angle between the nadir and the ground's tangent ray = atan(R, ρ),  θ_h = π − β
//   rows of the upper half (rays above the ground horizon):  θ = θ_h (1 − (1 − x)²), x ∈ [0, 1]
//   rows of the lower half (rays that hit the ground):        θ = θ_h + β y²,          y ∈ [0, 1]
// Each half puts its end values on texel centres, so a lookup for a sky ray never blends in a
// ground texel (and vice versa) — no band at the horizon. The height must be even.
// Azimuth is linear, u ∝ φ: the LUT stores phase-free Rayleigh/Mie integrals (the phase is
// applied per pixel), so the sun side needs no extra texels (Hillaire squeezes u toward the sun
// because his LUT holds the Mie peak).
// Valid from any camera height r ≥ R, including space (θ_h then grows past 90°).
// =============================================================================================

float HillaireGroundAngle(float h) {      // β
    return atan(uBottomRadius, HillaireHorizonDistance(h));
}

// (θ, φ) for a texel (integer coordinates) of a LUT of the given size.
vec2 HillaireSkyViewAngles(ivec2 texel, ivec2 size, float h) {
    float beta = HillaireGroundAngle(h);
    float thetaH = PI - beta;
    int half_ = size.y / 2;
    float denom = float(max(half_ - 1, 1));
    float theta;
    // The rows at the horizon hold the limits from above and from below (1e-4 rad off the
    // tangent ray, so each is integrated as a sky or as a ground ray for certain).
    if (texel.y < half_) {
        float x = float(texel.y) / denom;
        theta = min(thetaH * (1.0 - (1.0 - x) * (1.0 - x)), thetaH - 1.0e-4);
    } else {
        float y = float(texel.y - half_) / denom;
        theta = thetaH + max(beta * y * y, 1.0e-4);
    }
    float phi = PI * float(texel.x) / float(max(size.x - 1, 1));
    return vec2(theta, phi);
}

// Texture coordinates of the direction (μ = cos θ, cos φ) for a LUT of the given size.
// acos to within 7e-5 rad (Abramowitz & Stegun 4.4.45: a cubic in |x| times sqrt(1 − |x|)), a
// few thousandths of a sky-view texel: the lookup's two arc cosines per pixel are most of its
// arithmetic on a software renderer, whose acos is a long polynomial.
float HillaireAcos(float x) {
    float a = min(abs(x), 1.0);
    float r = sqrt(1.0 - a) * (1.5707288 + a * (-0.2121144 + a * (0.0742610 - 0.0187293 * a)));
    return x < 0.0 ? PI - r : r;
}

// The texture coordinates of (μ, cos φ) at altitude h, with β = HillaireGroundAngle(h) and the
// ground horizon's cosine muHorizon = HillaireHorizonCosine(h) given (per frame, from the CPU:
// a lookup per pixel then pays for no atan, square root or division of its own).
vec2 HillaireSkyViewUvAt(float mu, float cosPhi, vec2 size, float beta, float muHorizon) {
    float thetaH = PI - beta;
    float theta = HillaireAcos(mu);
    float halfRows = floor(size.y * 0.5);
    float row;
    if (!(mu < muHorizon)) {
        float x = 1.0 - sqrt(clamp(1.0 - theta / thetaH, 0.0, 1.0));
        row = 0.5 + x * (halfRows - 1.0);
    } else {
        float y = sqrt(clamp((theta - thetaH) / max(beta, 1.0e-6), 0.0, 1.0));
        row = halfRows + 0.5 + y * (halfRows - 1.0);
    }
    float phi = HillaireAcos(cosPhi);
    float col = 0.5 + phi / PI * (size.x - 1.0);
    return vec2(col, row) / size;
}

vec2 HillaireSkyViewUv(float mu, float cosPhi, vec2 size, float h) {
    return HillaireSkyViewUvAt(mu, cosPhi, size, HillaireGroundAngle(h), HillaireHorizonCosine(h));
}
