// Tone mapping for display. Twin: app/colour.py (tonemap, linear_to_srgb); PNG files use the
// twin, the window uses this file, and a GL test of the display pass checks they agree.
// Modes: 0 = ACES filmic (Narkowicz 2015 fit), 1 = Reinhard x/(1+x), 2 = clamp,
// 3 = exponential 1 − e^(−x) (O'Neil's exposure, spec/002 §1.6).

vec3 TonemapACES(vec3 x) {
    const float a = 2.51, b = 0.03, c = 2.43, d = 0.59, e = 0.14;
    return clamp((x * (a * x + b)) / (x * (c * x + d) + e), 0.0, 1.0);
}

vec3 Tonemap(vec3 radiance, float exposure, int mode) {
    vec3 x = max(radiance * exposure, vec3(0.0));
    if (mode == 0) return TonemapACES(x);
    if (mode == 1) return x / (1.0 + x);
    if (mode == 3) return 1.0 - exp(-x);
    return clamp(x, 0.0, 1.0);
}

vec3 LinearToSrgb(vec3 c) {
    c = clamp(c, 0.0, 1.0);
    vec3 lo = 12.92 * c;
    vec3 hi = 1.055 * pow(c, vec3(1.0 / 2.4)) - 0.055;
    return mix(hi, lo, vec3(lessThanEqual(c, vec3(0.0031308))));
}

vec3 SrgbToLinear(vec3 c) {
    c = clamp(c, 0.0, 1.0);
    vec3 lo = c / 12.92;
    vec3 hi = pow((c + 0.055) / 1.055, vec3(2.4));
    return mix(hi, lo, vec3(lessThanEqual(c, vec3(0.04045))));
}
