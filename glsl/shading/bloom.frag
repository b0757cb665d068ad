#version 330 core
// Bloom as a post pass (spec/003 §2.14: named by the thesis as future work, not implemented
// there), program fullscreen("shading/bloom"): common/fullscreen.vert + this file, drawn in
// four passes by app.effects.shading.outlines.Outlines.bloom:
//   uPass 0  bright pass at half resolution: one bilinear tap at the centre of each 2 × 2 block
//            (their mean), scaled by max(L − uThreshold, 0) / L, L = the luminance (Rec. 709
//            weights) — what lies above the threshold, hue kept;
//   uPass 1  a separable Gaussian along uDirection (one texel of the half-resolution image),
//            run twice (x, then y): radius uRadiusPx full-resolution pixels, i.e. uRadiusPx / 2
//            half-resolution texels, σ = radius / 2, weights normalised; at most 32 taps a side;
//   uPass 2  the blurred image × uIntensity, added to the image (blend one, one; alpha kept).
//
// Failure cases guarded: NaN or infinite input is dropped (0) and the bright part is clamped to
// 1e4 so one bad pixel cannot flood the frame; L = 0 divides by nothing (a dark image stays
// exactly dark: nothing passes a threshold > 0); a radius below half a texel is a copy; taps off
// the image are clamped to its edge (the border brightens slightly, not wraps).
in vec2 vUV;

uniform sampler2D uSource;   // pass 0: the image (full size); passes 1, 2: the half-size bloom
uniform int uPass;
uniform float uThreshold;    // luminance above which light blooms
uniform vec2 uDirection;     // pass 1: one texel of uSource along the blur axis (in uv)
uniform float uRadiusPx;     // blur radius, full-resolution pixels
uniform float uIntensity;    // pass 2: the bloom's gain

out vec4 fragColor;

vec3 Finite(vec3 c) {
    return vec3(isnan(c.r) || isinf(c.r) ? 0.0 : c.r, isnan(c.g) || isinf(c.g) ? 0.0 : c.g,
                isnan(c.b) || isinf(c.b) ? 0.0 : c.b);
}

void main() {
    if (uPass == 0) {
        vec3 c = max(Finite(texture(uSource, vUV).rgb), vec3(0.0));
        float l = dot(c, vec3(0.2126, 0.7152, 0.0722));
        vec3 bright = l > 0.0 ? c * (max(l - uThreshold, 0.0) / l) : vec3(0.0);
        fragColor = vec4(min(bright, vec3(1e4)), 1.0);
    } else if (uPass == 1) {
        float radius = 0.5 * uRadiusPx;
        int taps = min(int(ceil(radius)), 32);
        float sigma = max(0.5 * radius, 1e-3);
        vec3 sum = texture(uSource, vUV).rgb;
        float total = 1.0;
        for (int i = 1; i <= taps; ++i) {
            float w = exp(-0.5 * float(i * i) / (sigma * sigma));
            sum += w * (texture(uSource, vUV + float(i) * uDirection).rgb
                        + texture(uSource, vUV - float(i) * uDirection).rgb);
            total += 2.0 * w;
        }
        fragColor = vec4(sum / total, 1.0);
    } else {
        fragColor = vec4(max(uIntensity, 0.0) * Finite(texture(uSource, vUV).rgb), 0.0);
    }
}
