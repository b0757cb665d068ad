#version 330 core
// The shared shadow caster's fragment stage (spec/003 §2.8): alpha cutout, the thesis's
// dithered semitransparent shadows (17 4×4 patterns of 0..16 dots, Unity's _DitherMaskLOD,
// pattern round(16 α) at gl_FragCoord mod 4; the patterns are the ordered-dither Bayer 4×4
// thresholds, twin app/sim/shadows.py dither_patterns), and the colour the map needs:
// kind 0/1 the depth moments (d, d²) for VSM, kind 2 the point light's (|l| + linear bias) /
// range (UnityEncodeCubeShadowDepth; twin point_encode).
// Interface: uAlphaMode (0 opaque, 1 cutout, 2 dithered), uOpacity, uCutoff, uAlphaTex (.a);
// uShadowCasterKind, uShadowCasterLight, uShadowCasterRange, uShadowCasterPointBias (metres).
// Failure cases guarded: α outside [0, 1] or NaN is clamped (pattern 0..16 only); a range ≤ 0
// writes 1 (never a division by zero).
in vec3 vWorld;
in vec2 vUV;

uniform int uAlphaMode;
uniform float uOpacity;
uniform float uCutoff;
uniform sampler2D uAlphaTex;
uniform int uShadowCasterKind;
uniform vec3 uShadowCasterLight;
uniform float uShadowCasterRange;
uniform float uShadowCasterPointBias;

out vec4 fragColor;

const int BAYER4[16] = int[16](0, 8, 2, 10, 12, 4, 14, 6, 3, 11, 1, 9, 15, 7, 13, 5);

void main() {
    if (uAlphaMode != 0) {
        float a = texture(uAlphaTex, vUV).a * uOpacity;
        a = isnan(a) ? 0.0 : clamp(a, 0.0, 1.0);
        if (uAlphaMode == 1 && a < uCutoff) discard;
        if (uAlphaMode == 2) {
            ivec2 q = ivec2(gl_FragCoord.xy) & 3;
            if (BAYER4[q.y * 4 + q.x] >= int(floor(a * 16.0 + 0.5))) discard;
        }
    }
    float d = gl_FragCoord.z;
    if (uShadowCasterKind == 2) {
        d = uShadowCasterRange > 0.0
            ? (length(vWorld - uShadowCasterLight) + uShadowCasterPointBias) / uShadowCasterRange
            : 1.0;
    }
    fragColor = vec4(d, d * d, 0.0, 1.0);
}
