// =============================================================================================
// Method 4 — the aerial-perspective volume (Hillaire 2020 §5.4; 32 × 32 × 32 froxels over the
// camera frustum in the paper), shared by the compute pass (aerial_perspective.comp) and the
// fragment fallback (aerial_perspective.frag, one slice row per fragment row, for GL < 4.3).
//
// Texel (x, y) is the ray CameraRayDirection((x + ½, y + ½)/size) of the current camera; slice k
// holds the integral from the camera to the distance d(k + 1), with
//   d(s) = range · (s / D)²                   (quadratic: fine near the camera — 125 m for the
//                                              first slice at the default 128 km / 32 slices)
// so that a lookup at distance t reads slice coordinate s = D sqrt(t / range).
// Each slice is cut into uHillaireApSubsteps midpoint samples, clipped to the atmosphere
// segment of the ray (from space the part before the entry point contributes nothing; past the
// top the values repeat). Columns are not clipped at the ground (see HillaireApColumn).
// Volume 0: rgb = P_R(ν) ∫T T_sun σ_R + ∫T σ_s Ψ_ms, a = ∫ρ_R dt; volume 1: rgb = ∫T T_sun σ_M
// (no phase: the lookup applies P_M of the pixel's own ν), a = ∫ρ_M dt (the lookup's
// per-channel transmittance). Radiances per unit sun intensity.
//
// The compute path marches each column once and stores every slice; the fragment path marches
// the same samples in the same order and stops at its slice — both give the same numbers.
// Failure cases: camera above the top (columns start at the entry point; the lookup blends to a
// per-pixel march there anyway), rays that never enter the atmosphere (0, T = 1).
// =============================================================================================
uniform ivec3 uHillaireApSize;      // (x, y, slices)
uniform float uHillaireApRange;     // distance of the last slice (m)
uniform int uHillaireApSubsteps;    // midpoint samples per slice

float HillaireApSliceDistance(float s) {
    float x = s / float(uHillaireApSize.z);
    return uHillaireApRange * x * x;
}

// March column `texel` up to slice `lastSlice` (all of them when < 0); the values of the last
// slice marched are returned (and, with HILLAIRE_AP_STORE defined, every slice is stored).
void HillaireApColumn(ivec2 texel, int lastSlice, out vec4 rayleighMultiple, out vec4 mie) {
    vec2 uv = (vec2(texel) + 0.5) / vec2(uHillaireApSize.xy);
    vec3 dir = CameraRayDirection(uv);
    vec3 up = CameraUp();
    float h0 = uHillaireCameraHeight;
    float mu = ClampCosine(dot(dir, up));
    float muS = ClampCosine(dot(uSunDir, up));
    float nu = ClampCosine(dot(dir, uSunDir));
    float phaseR = PhaseRayleigh(nu);
    // Not clipped at the ground: past its ground point a column goes on through air at h = 0
    // (DensityRM clamps h), so its values stay continuous with the neighbouring columns that
    // pass above the horizon and trilinear filtering at the horizon does not mix in a plateau.
    // A surface never reads past its own ray's ground point, so this changes no exact value.
    vec2 seg = HillaireRaySegmentClipped(h0, mu, HILLAIRE_INFINITY, false);
    HillaireInScatter acc = HillaireZeroInScatter();
    int n = max(uHillaireApSubsteps, 1);
    int last = lastSlice < 0 ? uHillaireApSize.z - 1 : lastSlice;
    rayleighMultiple = vec4(0.0);
    mie = vec4(0.0);
    for (int k = 0; k <= last; ++k) {
        float d0 = HillaireApSliceDistance(float(k));
        float d1 = HillaireApSliceDistance(float(k + 1));
        for (int j = 0; j < n; ++j) {
            float ta = max(d0 + (d1 - d0) * float(j) / float(n), seg.x);
            float tb = min(d0 + (d1 - d0) * float(j + 1) / float(n), seg.y);
            if (tb > ta) HillaireAccumulate(acc, h0, mu, muS, nu, 0.5 * (ta + tb), tb - ta, true);
        }
        rayleighMultiple = vec4(phaseR * acc.rayleigh + uHillaireMsScale * acc.multiple,
                                acc.density.x);
        mie = vec4(acc.mie, acc.density.y);
#ifdef HILLAIRE_AP_STORE
        HILLAIRE_AP_STORE(ivec3(texel, k), rayleighMultiple, mie);
#endif
    }
}
