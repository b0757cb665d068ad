// =============================================================================================
// Marble and granite — beyond the procedural-wood thesis, which names them only as uses of
// procedural textures (spec/004 §1.1, §1.5: "noise used directly as colour looks like granite").
//
// Marble (Perlin 1985's classic): veins are a sine of one coordinate pushed around by turbulence,
//   s = ½ + ½ sin(2π (VeinFrequency · p.x + Turbulence · T(p))),   T(p) = Σ_i gain^i |n(2^i p)|
//   v = s^Sharpness,  colour = mix(VeinColor, BaseColor, v)
// Granite: speckles from a high-frequency fBm F(p) = Σ_i gain^i n(2^i p) / Σ_i gain^i:
//   dark grains where F < −Threshold, light grains where F > Threshold, the matrix colour between,
//   with a narrow smooth edge so the grains do not shimmer.
// n is the scalar noise chosen by the "noise" switch: the thesis's value noise mapped to
// [−1, 1] or Perlin's gradient noise, so students compare the two on the same material.
// =============================================================================================

uniform float uMarbleScale;        // object-space frequency of the turbulence
uniform float uMarbleVeinFrequency;
uniform float uMarbleTurbulence;
uniform float uMarbleSharpness;
uniform int uMarbleOctaves;
uniform vec3 uMarbleBaseColor;
uniform vec3 uMarbleVeinColor;

uniform float uGraniteScale;
uniform int uGraniteOctaves;
uniform float uGraniteThreshold;
uniform vec3 uGraniteDarkColor;
uniform vec3 uGraniteMatrixColor;
uniform vec3 uGraniteLightColor;

float MaterialNoise1(vec3 p);  // defined by material.frag from the noise switch

// Turbulence: Σ 2^-i |noise(2^i p)| over up to 10 octaves (not normalised), p in object units.
float MaterialTurbulence(vec3 p, int octaves) {
    float sum = 0.0, amp = 1.0, freq = 1.0;
    for (int i = 0; i < 10; ++i) {
        if (i >= octaves) break;
        sum += amp * abs(MaterialNoise1(p * freq));
        amp *= 0.5;
        freq *= 2.0;
    }
    return sum;
}

// fBm: Σ 2^-i noise(2^i p) / Σ 2^-i over up to 10 octaves, p in object units. Failure case:
// octaves < 1 sums nothing and gives 0/0, so the octave parameter must stay ≥ 1.
float MaterialFbm(vec3 p, int octaves) {
    float sum = 0.0, total = 0.0, amp = 1.0, freq = 1.0;
    for (int i = 0; i < 10; ++i) {
        if (i >= octaves) break;
        sum += amp * MaterialNoise1(p * freq);
        total += amp;
        amp *= 0.5;
        freq *= 2.0;
    }
    return sum / total;
}

vec3 MarbleColor(vec3 objectPos) {
    vec3 p = objectPos * uMarbleScale;
    float t = MaterialTurbulence(p, uMarbleOctaves);
    float s = 0.5 + 0.5 * sin(TWO_PI * (uMarbleVeinFrequency * objectPos.x
                                        + uMarbleTurbulence * t));
    return mix(uMarbleVeinColor, uMarbleBaseColor, pow(s, uMarbleSharpness));
}

vec3 GraniteColor(vec3 objectPos) {
    float f = MaterialFbm(objectPos * uGraniteScale, uGraniteOctaves);
    float edge = 0.03;
    float dark = 1.0 - smoothstep(-uGraniteThreshold - edge, -uGraniteThreshold + edge, f);
    float light = smoothstep(uGraniteThreshold - edge, uGraniteThreshold + edge, f);
    vec3 c = mix(uGraniteMatrixColor, uGraniteDarkColor, dark);
    return mix(c, uGraniteLightColor, light);
}
