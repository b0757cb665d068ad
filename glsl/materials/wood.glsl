// =============================================================================================
// Wood growth rings as a volumetric procedural texture — procedural-wood thesis
// (spec/004 §1.4, §1.6, §1.7; thesis §4.1 and ch. 5).
//
//   noiseCoords  = pos · NoiseGridSize.xyz · NoiseGridSize.w
//   distor       = (octaves(noiseCoords, RecDepth) − 0.5) · DistorFactor.xyz · DistorFactor.w
//   volTexCoords = pos · VolTexScale.xyz · VolTexScale.w + distor   (distort the point, §4.2)
//   radius       = √(x² + z²) of volTexCoords             (rings about the Y axis, §4.1 step 1)
//   value        = easeIn(radius mod 1) = (radius mod 1)²     (w(x) = (x/T) mod 1, g(t) = t²)
//   colour       = lerp(InnerColor, OuterColor, value)                  (C∘g∘w, §4.1 step 5)
//
// Every output colour is on the segment Inner–Outer: with the defaults R − G = G − B = 0.25.
// Failure case, beyond the thesis: the ring jump at each radius k aliases under minification;
// WoodRingValue(…, filtered = true) box-filters g∘w over the pixel footprint exactly, using the
// antiderivative F(x) = (floor(x) + fract(x)³) / 3 of fract(x)².
// =============================================================================================

uniform vec4 uVolTexScale;    // thesis defaults (1, 1, 1, 10)
uniform vec4 uNoiseGridSize;  // (0.2, 1, 1, 10)
uniform vec4 uDistorFactor;   // (1, 1, 1, 0.5)
uniform vec3 uInnerColor;     // (0.75, 0.5, 0.25)
uniform vec3 uOuterColor;     // (0.5, 0.25, 0)
uniform int uRecDepth;        // octaves of the distortion noise (RecDepth, 1…8)

float WoodRingAntiderivative(float x) {
    float f = fract(x);
    return (floor(x) + f * f * f) / 3.0;
}

// Ring value v = g(w(radius)); filtered: its mean over [radius − width/2, radius + width/2].
float WoodRingValue(float radius, float width, bool filtered) {
    if (!filtered || width < 1.0e-6) {
        float t = mod(radius, 1.0);
        return t * t;  // easeIn: the thesis's clamps are no-ops on [0, 1)
    }
    float a = radius - 0.5 * width, b = radius + 0.5 * width;
    return (WoodRingAntiderivative(b) - WoodRingAntiderivative(a)) / (b - a);
}

vec3 WoodNoiseCoords(vec3 objectPos) { return objectPos * uNoiseGridSize.xyz * uNoiseGridSize.w; }

// noise01: the chosen noise at WoodNoiseCoords, three channels in [0, 1].
float WoodRadius(vec3 objectPos, vec3 noise01) {
    vec3 distor = (noise01 - 0.5) * uDistorFactor.xyz * uDistorFactor.w;
    vec3 volTexCoords = objectPos * uVolTexScale.xyz * uVolTexScale.w + distor;
    vec2 dis = volTexCoords.xz;
    dis *= dis;
    return sqrt(dis.x + dis.y);
}

vec3 WoodColor(float value) { return mix(uInnerColor, uOuterColor, value); }
