#version 330 core
// =============================================================================================
// Method 4, pass 1 — the transmittance LUT (Hillaire 2020 §4, "Transmittance LUT"; 256 × 64 in
// the paper). Texel (x_μ, x_r) ↦ the ray (h, μ) of Bruneton's parametrisation
// (hillaire_common.glsl) ↦ T(h, μ) = exp(−(β^ext_R τ_R + β^ext_M τ_M)) to the top of the
// atmosphere, with τ_x = ∫ ρ_x(h(t)) dt (spec/002 §1.3; e^(−τ), not ×τ — §1.4 erratum), plus the
// ozone layer's σ_a τ_O when it is on (model.glsl; beyond the thesis).
//
// Integration: midpoint sum in s with t = d s³, dt = 3 d s² ds (uHillaireTransmittanceSteps
// samples). The cubic map puts the samples where the density is: against a 256 000-sample
// Gauss–Legendre reference the relative error in τ is ≤ 2·10⁻⁵ at 40 samples for every
// (h, μ) tested, where 40 uniform samples give 6 % (vertical Mie from the ground).
//
// Rebuilt only when β, H, P0 or the radii change (app/effects/planet/hillaire.py).
// Failure cases: rays that hit the ground are not in this table (its μ range stops at the
// tangent ray); callers multiply by the planet-shadow test. x_r = 1 is the top, where T = 1.
// =============================================================================================
#include "hillaire_common.glsl"

in vec2 vUV;
out vec4 fragColor;
uniform vec2 uHillaireTargetSize;       // LUT size in texels
uniform int uHillaireTransmittanceSteps;

// (∫ρ_R dt, ∫ρ_M dt, ∫ρ_O dt) from altitude h to the top along μ.
vec3 HillaireOpticalDepthToTop(float h, float mu, int steps) {
    float d = HillaireDistanceToTop(h, mu);
    float n = float(max(steps, 1));
    vec3 depth = vec3(0.0);
    for (int i = 0; i < max(steps, 1); ++i) {
        float s = (float(i) + 0.5) / n;
        float t = d * s * s * s;
        depth += DensityRMO(HillaireHeightAlong(h, mu, t)) * (3.0 * d * s * s / n);
    }
    return depth;
}

void main() {
    vec2 unit = (floor(gl_FragCoord.xy) + 0.0) / max(uHillaireTargetSize - 1.0, vec2(1.0));
    float h, mu;
    HillaireTransmittanceParams(unit, h, mu);
    vec3 depth = HillaireOpticalDepthToTop(h, mu, uHillaireTransmittanceSteps);
    fragColor = vec4(TransmittanceFromDepths(depth), 1.0);
}
