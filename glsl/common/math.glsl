// Small shared helpers. Twins where tests need them: saturate is sat in app/sim/clouds.py;
// SmoothStepDown(hi, lo, x) is smoothstep(hi, lo, x) in app/sim/sky.py. SchlickFresnel lives in
// fresnel.glsl (the project's one Fresnel).
const float PI = 3.14159265358979;
const float TWO_PI = 6.28318530717959;
const float HALF_PI = 1.57079632679490;

// spec/001 eq. 4.2: Sat(v) = clamp(v, 0, 1)
float saturate(float x) { return clamp(x, 0.0, 1.0); }
vec3 saturate(vec3 x) { return clamp(x, 0.0, 1.0); }

// Clamp a cosine into [-1, 1] before acos/asin: rounding can push a dot product of unit
// vectors past 1, and acos(1.0000001) is NaN.
float ClampCosine(float mu) { return clamp(mu, -1.0, 1.0); }

float SafeSqrt(float x) { return sqrt(max(x, 0.0)); }

// x normalised, or ``fallback`` for a (near) zero vector (an interpolated normal that vanished,
// a point at the camera): never a NaN from normalize(vec3(0)).
vec3 SafeNormalize(vec3 x, vec3 fallback) {
    float len2 = dot(x, x);
    return len2 > 1e-20 ? x * inversesqrt(len2) : fallback;
}

// GLSL's smoothstep(e0, e1, x) is undefined when e0 >= e1, so the reversed ramps HLSL code
// writes as smoothstep(0.6, 0.0, x) are written out by hand:
// SmoothStepDown(hi, lo, x) = 1 - smoothstep(lo, hi, x), i.e. 1 at x <= lo and 0 at x >= hi.
float SmoothStepDown(float hi, float lo, float x) {
    float t = clamp((x - lo) / (hi - lo), 0.0, 1.0);
    return 1.0 - t * t * (3.0 - 2.0 * t);
}
