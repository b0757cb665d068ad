// =============================================================================================
// The staircase functions of the toon look (spec/003 §2.10, §2.13): the colour discretisation
// of the toon water's reflection and the soft staircase of the rim silhouettes, one function per
// equation, plus the two other silhouette shapings of spec/003 §2.13 (threshold and 50x²).
//
//   StaircaseStepY(sx)          step_y = step_x / (1 − step_x)                spec/003 eq. 7.18
//   StaircaseFloor(x, sx)       x − (x mod step_x)                             spec/003 eq. 7.19
//   StaircaseLevel(xf, sx)      (x / step_x) · step_y                          spec/003 eq. 7.20
//   StairedValue(x, sx)         the three composed, the top level clamped to 1: with 1/step_x
//                               an integer N the levels are k/(N − 1), k = 0 … N − 1, for
//                               x in [0, 1) (#steps_y = #steps_x − 1)
//   SoftStairWeightMin(d, ss)   weight_min = ½ − d/step_soft                   spec/003 eq. 8.2
//   SoftStairWeightMax(d, s, ss) weight_max = ½ − (step − d)/step_soft         spec/003 eq. 8.3
//   SoftStairOffsets(d, s, ss)  e_min = −step·weight_min if d < step_soft/2,
//                               e_max = +step·weight_max if step − d < step_soft/2 spec/003 eq. 8.4
//   SoftStairedValue(x, s, ss)  saturate((x − d) + e_min + e_max), d = x mod step: the hard
//                               staircase of height `step` with each jump replaced by a ramp of
//                               width step_soft and slope step/step_soft (continuous for
//                               0 < step_soft ≤ step)
//   ThresholdStep(x, t)         1 where x > t, else 0 (the first rim silhouette)
//   SoftSilhouette(x)           saturate(50·x²) (the third; "50x²", confirmed by the repository)
//
// "x mod s" is GLSL's mod, x − s·floor(x/s) (the repository's HLSL fmod differs only for x < 0,
// where no caller of the thesis evaluates it).
// Failure cases guarded: step_x = 1 would divide by zero in spec/003 eq. 7.18 and step_x = 0 in
// spec/003 eq. 7.19 — both are clamped into [1e-4, 1 − 1e-4]; step_soft = 0 (the hard staircase)
// would divide by zero in spec/003 eq. 8.2 — the offsets are then zero, so the soft staircase
// equals the hard one exactly; the weights are saturated (as the repository does) so a
// step_soft > step cannot push the offsets past half a step.
// Numpy twin: app/sim/staircase.py (same names in snake case; tests/unit/test_staircase.py).
// =============================================================================================
float StaircaseSafeStep(float stepX) { return clamp(stepX, 1e-4, 1.0 - 1e-4); }

// spec/003 eq. 7.18: the height of one step of the output, step_y = step_x / (1 − step_x).
float StaircaseStepY(float stepX) {
    float s = StaircaseSafeStep(stepX);
    return s / (1.0 - s);
}

// spec/003 eq. 7.19: x ← x − (x mod step_x), x floored to its step.
float StaircaseFloor(float x, float stepX) {
    return x - mod(x, StaircaseSafeStep(stepX));
}

// spec/003 eq. 7.20: x ← (x / step_x) · step_y, the step's index times the output step.
float StaircaseLevel(float xFloored, float stepX) {
    return xFloored / StaircaseSafeStep(stepX) * StaircaseStepY(stepX);
}

// The colour discretisation of spec/003 §2.10 (GetStairedValue): spec/003 eq. 7.19 then
// spec/003 eq. 7.20, clamped to 1 (the top step of x = 1 would lie above it).
float StairedValue(float x, float stepX) {
    return min(StaircaseLevel(StaircaseFloor(x, stepX), stepX), 1.0);
}
vec3 StairedValue(vec3 x, float stepX) {
    return vec3(StairedValue(x.r, stepX), StairedValue(x.g, stepX), StairedValue(x.b, stepX));
}

// spec/003 eq. 8.2: weight_min = ½ − d/step_soft (saturated division), d the position in a step.
float SoftStairWeightMin(float d, float stepSoft) {
    return 0.5 - clamp(d / max(stepSoft, 1e-8), 0.0, 1.0);
}

// spec/003 eq. 8.3: weight_max = ½ − (step − d)/step_soft (saturated division).
float SoftStairWeightMax(float d, float stepSize, float stepSoft) {
    return 0.5 - clamp((stepSize - d) / max(stepSoft, 1e-8), 0.0, 1.0);
}

// spec/003 eq. 8.4: e_min + e_max, each only within half a soft step of its jump.
float SoftStairOffsets(float d, float stepSize, float stepSoft) {
    if (stepSoft <= 0.0) return 0.0;
    float half_ = 0.5 * stepSoft;
    float eMin = d < half_ ? -stepSize * SoftStairWeightMin(d, stepSoft) : 0.0;
    float eMax = stepSize - d < half_ ? stepSize * SoftStairWeightMax(d, stepSize, stepSoft) : 0.0;
    return eMin + eMax;
}

// The soft staircase of spec/003 §2.13 (GetSoftStairedValue): the hard staircase x − d plus the
// offsets of spec/003 eq. 8.4, saturated.
float SoftStairedValue(float x, float stepSize, float stepSoft) {
    float s = max(stepSize, 1e-4);
    float d = mod(x, s);
    return clamp(x - d + SoftStairOffsets(d, s, stepSoft), 0.0, 1.0);
}

// The first rim silhouette of spec/003 §2.13: binary, 1 above the threshold.
float ThresholdStep(float x, float threshold) { return x > threshold ? 1.0 : 0.0; }

// The third rim silhouette of spec/003 §2.13: a fast smooth 0 → 1 transition, saturate(50·x²).
float SoftSilhouette(float x) { return clamp(50.0 * x * x, 0.0, 1.0); }
