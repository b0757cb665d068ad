// From the eight real fields of one cascade to the textures the ocean surface samples, and
// foam — spec/000 §1.1(d) (choppy displacement, spectral normals), the Jacobian of the
// horizontal displacement (Tessendorf 2001, §4.4 "Choppy waves": folds where J < 0) and the
// foam rule of app/sim/ocean.py foam_step (its numpy twin):
//
//   J = (1 + λ∂D_x/∂x)(1 + λ∂D_z/∂z) − (λ∂D_x/∂z)²
//   foam ← max(foam·e^{−dt/τ}, clamp((threshold − J)/width, 0, 1))
// (width = threshold: the upstream's ramp; the ocean's whitecap mode sets both per cascade so
// the foam covers Monahan & O'Muircheartaigh's fraction of the sea, app/sim/ocean.py)
//
// Inputs after the inverse FFT (see spectrum_evolve.glsl):
//   fields0 = (η, λD_x, λD_z, ∂η/∂x),  fields1 = (∂η/∂z, λ∂D_x/∂x, λ∂D_z/∂z, λ∂D_x/∂z).
// Outputs: disp = (λD_x, η, λD_z, J), deriv = (∂η/∂x, ∂η/∂z, λ∂D_x/∂x, λ∂D_z/∂z).
//
// Failure cases guarded: folds (J ≤ 0) are kept as they are — J is a signal, the source clamps
// to 1 there; the decay factor e^{−max(dt, 0)/τ} comes from the CPU in float64 (dt ≤ 0 → 1: a
// paused or reversed clock never grows foam or divides by zero); threshold > 0 and τ > 0 are
// checked on the CPU (ParamError).

uniform float uFoamThreshold;  // J below this makes foam (> 0)
uniform float uFoamWidth;      // J range over which the source ramps from 0 to 1 (> 0)
uniform float uFoamDecay;      // e^{−max(dt,0)/τ}, in (0, 1]
uniform int uFoamUpdate;       // 0: carry the foam over unchanged (direct-sum reference)

float OceanJacobian(vec4 fields1) {
    return (1.0 + fields1.y) * (1.0 + fields1.z) - fields1.w * fields1.w;
}

float FoamSource(float jacobian) {
    return clamp((uFoamThreshold - jacobian) / uFoamWidth, 0.0, 1.0);
}

void FinalizeOceanTexel(vec4 fields0, vec4 fields1, float foamBefore,
                        out vec4 disp, out vec4 deriv, out float foam) {
    float jacobian = OceanJacobian(fields1);
    disp = vec4(fields0.y, fields0.x, fields0.z, jacobian);
    deriv = vec4(fields0.w, fields1.x, fields1.y, fields1.z);
    foam = uFoamUpdate != 0 ? max(foamBefore * uFoamDecay, FoamSource(jacobian)) : foamBefore;
}
