// =============================================================================================
// Lighting and toon models of the toon-village thesis (spec/003 §2.1, spec/003 §2.12): the
// shading lab's surface.vert (the Gouraud path: lit per vertex, interpolated) and surface.frag
// (the thesis's per-fragment path), and the village's CelShader and ComplexCelShader objects,
// which pass the sun's shadow visibility (ShadeSurfaceShadowed). Its @param uniforms belong to
// the group of the effect whose program includes it (shading.toon, village.toon, ...). All directions are world-space unit vectors: n the normal, v toward the
// camera, l toward the light.
//
// Lighting models (spec/003 §2.1), chosen by uLightingModel:
//   0 Lambert      k_diff = max(0, n·l)                                  (spec/003 §2.1)
//   1 Phong        k_spec = max(0, r·v)^n, r = reflect(−l, n)            (spec/003 §2.1)
//   2 Blinn–Phong  h = (l + v)/‖l + v‖                                    spec/003 eq. 2.1
//                  k_spec = max(0, n·h)^m                                 spec/003 eq. 2.2
//   rim            k_rim = (1 − max(0, n·v))^m, added as a colour (uRimColor)  (spec/003 §2.1)
// Toon (spec/003 §2.12, the CelShader's Toon popup), chosen by uToon; x = ½(n·l) + ½ is the
// remapped n·l of spec/003 eq. 8.1:
//   0 None     diffuse max(0, n·l), specular k_spec of the lighting model
//   1 Flat     one cut at the terminator: 0.25 + 0.75·E(x), E(y) = smoothstep(½ − w, ½ + w, y),
//              w = 0.25·(1 − Smoothness) — Smoothness 1 is the hard edge (two levels, cut at
//              n·l = 0), lower values soften it (Fig. 127b's 1, 0.75, 0.5); the specular is the
//              same edge on k_spec, E(k_spec): hard-edged. Levels 0.25/1 and the edge form are
//              the public repository's (spec/003 Appendix A), the cut at n·l = 0 the document's.
//   2 Stepped  the document's table on x: ≤ 0.45 → 0.2, ≤ 0.55 → 0.5, ≤ 0.65 → 0.7, else 1.0
//              (n·l = −0.1, 0.1, 0.3); with uSteppedRepository the public repository's table
//              (spec/003 Appendix A) on y = saturate(n·l)·atten instead: ≤ 0 → 0.2, ≤ 0.15 → 0.5,
//              ≤ 0.30 → 0.7, else 1.0 — the two differ for n·l in (−0.1, 0] (0.5 vs 0.2) and
//              (0.1, 0.15] (0.7 vs 0.5). The floor 0.2 is the thesis's built-in ambient. The
//              specular is the repository's soft staircase SoftStairedValue(saturate(4·k − 1.5),
//              0.25, 0.1·(1 − Smoothness)) (staircase.glsl).
//   3 Ramp     diffuse = ramp(x)·albedo, the 1-D ramp texture uRamp (W × 1) sampled at x
//              (spec/003 eq. 8.1); specular k_spec of the lighting model.
// Every specular is weighted by Specularity and the Specular (G) mask (ComplexCelShader); the
// specular colour is the light's. The Emission (R) mask adds uEmissionColor·R·flicker(t) with
//   flicker(t) = 1 − Flickering·f(t),
//   f(t) = ½ + ¼·sin(2π·1.3t) + 0.15·sin(2π·3.7t + 1.1) + 0.1·sin(2π·7.9t + 2.3) ∈ [0, 1]
// (three incommensurate sines: a candle-like irregular flicker; the thesis names Flickering a
// time-varying intensity only, so the function is ours). With Flickering 0 an emissive pixel is
// exactly uEmissionColor, light or no light.
//
// Forward accumulation (spec/003 §0, §1: Unity's ForwardBase pass for the main directional
// light, one additive ForwardAdd pass per further light, blended One One). Here in one pass:
//   ShadeForwardBase  = uAmbient·albedo + ShadeLight(sun) + rim + emission   (once)
//   ShadeForwardAdd   = Σ ShadeLight(point i) + ShadeLight(spot)            (each further light)
//   ShadeSurface      = ShadeForwardBase + ShadeForwardAdd — the same sum the blended passes make.
// ShadeLight(n, v, l, radiance, atten, albedo, specMask) is one light: radiance·atten·(albedo·D
// + Specularity·specMask·S), atten the light's distance and cone factor (the repository's
// Stepped variant thresholds saturate(n·l)·atten, so atten is passed apart from radiance).
// Lights (beyond the thesis, which uses Unity's): point attenuation (saturate(1 − (d/R)²))²,
// 1 at the light and 0 at its range R (no inverse square: finite at d = 0); the spot's cone
// smoothstep(cos_outer, cos_inner, cos angle) to the axis uSpotDir (written out: GLSL's
// smoothstep is undefined for equal edges), times the point attenuation over uSpotRange when
// uSpotRange > 0.
//
// Failure cases guarded: every normalisation of a possibly zero vector falls back (l + v = 0
// with the light exactly behind: h = 0, so no highlight; a point light at the surface: l = n;
// a zero normal: n = v); pow never sees a negative base (max(0, ·)) nor a zero exponent
// (≥ 1e-3); specular only where n·l > 0 (a highlight leaking through the terminator onto the
// unlit side — Phong's r·v > 0 there — is the failure Blinn–Phong's n·h avoids only in part);
// the spot's equal inner and outer cosines (a division by zero); uPointCount clamped to [0, 4];
// the ramp sampled with textureLod (defined in the vertex stage, where Gouraud samples it).
// Numpy twin: app/sim/lighting.py (snake-case names; tests/unit/test_lighting.py,
// tests/gl/test_shading_lighting.py).
// =============================================================================================
#include "math.glsl"
#include "staircase.glsl"

// ---- the model and toon choices (parameters of the shading group) ---------------------------
uniform int uLightingModel;        // @param 2 [0, 2] step=1 §2.1 lighting model: 0 Lambert, 1 Phong, 2 Blinn–Phong (the thesis's choice)
uniform float uPhongExponent;      // @param 60 [1, 500] step=1 §2.1 Phong shininess n of (r·v)^n (Fig. 18 shows 60 and 200)
uniform float uBlinnExponent;      // @param 120 [1, 1000] step=1 §2.1 Blinn–Phong exponent m of (n·h)^m (Fig. 20 shows 120 and 400)
uniform bool uRim;                 // @param false §2.1 rim light (1 − max(0, n·v))^m added as a colour
uniform float uRimPower;           // @param 2 [0.1, 16] step=0.1 §2.1 rim exponent m (Fig. 22 shows 2)
uniform vec3 uRimColor;            // @param (1, 1, 1) [0, 1] color §2.1 rim colour (added)
uniform int uToon;                 // @param 0 [0, 3] step=1 §2.12 CelShader Toon: 0 None, 1 Flat, 2 Stepped, 3 Ramp
// Specialisation (optional, as shadow.glsl's): a program compiled with LIGHTING_MODEL and
// LIGHTING_TOON defined reads them as constants instead of uLightingModel and uToon, so the
// models and toon modes it does not use are compiled out (a software rasteriser runs both sides
// of a branch on a uniform); the image is the same.
#ifdef LIGHTING_MODEL
#define LIGHTING_MODEL_VALUE LIGHTING_MODEL
#else
#define LIGHTING_MODEL_VALUE uLightingModel
#endif
#ifdef LIGHTING_TOON
#define LIGHTING_TOON_VALUE LIGHTING_TOON
#else
#define LIGHTING_TOON_VALUE uToon
#endif
uniform bool uSteppedRepository;   // @param false §2.12 Stepped with the public repository's thresholds (saturate(n·l)·atten: 0, 0.15, 0.30) instead of the document's (remapped n·l: 0.45, 0.55, 0.65)
uniform float uSpecularity;        // @param 0.168 [0, 1] step=0.001 §2.12 Specularity: weight of the specular (Fig. 130b shows 0.168)
uniform float uSmoothness;         // @param 0.841 [0, 1] step=0.001 §2.12 Smoothness: 1 hard Flat/Stepped edges, lower softer (Fig. 130b shows 0.841)
uniform vec3 uEmissionColor;       // @param (1, 0.75, 0.35) [0, 4] color §2.12 Emission Color where the Emission (R) mask is set
uniform float uFlicker;            // @param 0 [0, 1] step=0.01 §2.12 Flickering: depth of the emission's time variation (0 steady)

// ---- the material and the lights (set by the effect per object and per frame) ---------------
uniform vec3 uAlbedo;              // linear albedo
uniform sampler2D uRamp;           // the 1-D ramp of Toon = Ramp, a W × 1 texture
uniform sampler2D uMasks;          // R emission mask, G specular mask (when uUseMasks)
uniform bool uUseMasks;            // off: no emission, specular everywhere
uniform float uTime;               // seconds (the flicker)
uniform vec3 uAmbient;             // ambient radiance, added once (ForwardBase)
uniform vec3 uSunDir;              // toward the directional light (normalised here)
uniform vec3 uSunRadiance;         // its radiance (colour × intensity)
uniform vec3 uPointPos[4];
uniform vec3 uPointRadiance[4];
uniform float uPointRange[4];      // distance where the light reaches zero (≤ 0: no falloff)
uniform int uPointCount;           // 0 … 4
uniform vec3 uSpotPos;
uniform vec3 uSpotDir;             // the spot's axis, from the light outward
uniform vec3 uSpotRadiance;
uniform vec2 uSpotCos;             // cosines of the inner (full) and outer (zero) cone angles
uniform float uSpotRange;          // distance falloff of the spot (≤ 0: none)
uniform bool uSpotOn;

const float SPEC_MIN_EXPONENT = 1e-3;

// Lambert's diffuse term k_diff = max(0, n·l) (spec/003 §2.1).
float LambertTerm(vec3 n, vec3 l) { return max(dot(n, l), 0.0); }

// spec/003 eq. 2.1: the half vector h = (l + v)/‖l + v‖ (zero when l = −v: no highlight).
vec3 HalfVector(vec3 l, vec3 v) { return SafeNormalize(l + v, vec3(0.0)); }

// spec/003 eq. 2.2: Blinn–Phong's k_spec = max(0, n·h)^m.
float BlinnPhongTerm(vec3 n, vec3 h, float m) {
    return pow(max(dot(n, h), 0.0), max(m, SPEC_MIN_EXPONENT));
}

// Phong's k_spec = max(0, r·v)^n, r the mirror of l about n (spec/003 §2.1).
float PhongTerm(vec3 n, vec3 v, vec3 l, float e) {
    vec3 r = reflect(-l, n);
    return pow(max(dot(r, v), 0.0), max(e, SPEC_MIN_EXPONENT));
}

// The rim term k_rim = (1 − max(0, n·v))^m (spec/003 §2.1).
float RimTerm(vec3 n, vec3 v, float m) {
    return pow(1.0 - max(dot(n, v), 0.0), max(m, SPEC_MIN_EXPONENT));
}

// spec/003 eq. 8.1: the remapped n·l, x = ½(n·l) + ½ (0 at n·l = −1).
float RemappedNdotL(float ndotl) { return 0.5 * ndotl + 0.5; }

// The document's Stepped table on the remapped n·l (spec/003 §2.12).
float SteppedDocument(float x) {
    return x <= 0.45 ? 0.2 : (x <= 0.55 ? 0.5 : (x <= 0.65 ? 0.7 : 1.0));
}

// The public repository's Stepped table on saturate(n·l)·atten (spec/003 Appendix A).
float SteppedRepository(float y) {
    return y <= 0.0 ? 0.2 : (y <= 0.15 ? 0.5 : (y <= 0.30 ? 0.7 : 1.0));
}

// Flat's edge E(y) = smoothstep(½ − w, ½ + w, y), w = 0.25·(1 − smoothness), written out so
// that w = 0 (the hard edge) stays defined.
float FlatEdge(float y, float smoothness) {
    float w = 0.25 * (1.0 - clamp(smoothness, 0.0, 1.0));
    float t = clamp((y - (0.5 - w)) / max(2.0 * w, 1e-6), 0.0, 1.0);
    return t * t * (3.0 - 2.0 * t);
}

// Flat's diffuse: 0.25 + 0.75·E(½(n·l) + ½), cut at the terminator (spec/003 §2.12).
float FlatDiffuse(float ndotl, float smoothness) {
    return 0.25 + 0.75 * FlatEdge(RemappedNdotL(ndotl), smoothness);
}

// Stepped's specular: the repository's soft staircase of saturate(4k − 1.5) (staircase.glsl).
float SteppedSpecular(float k, float smoothness) {
    return SoftStairedValue(clamp(4.0 * k - 1.5, 0.0, 1.0), 0.25,
                            0.1 * (1.0 - clamp(smoothness, 0.0, 1.0)));
}

// The ramp of Toon = Ramp at ½(n·l) + ½ (spec/003 eq. 8.1).
vec3 RampColor(float ndotl) {
    return textureLod(uRamp, vec2(clamp(RemappedNdotL(ndotl), 0.0, 1.0), 0.5), 0.0).rgb;
}

// The lighting model's specular term, only where the light reaches the surface (n·l > 0).
float SpecularTerm(vec3 n, vec3 v, vec3 l) {
    if (dot(n, l) <= 0.0 || LIGHTING_MODEL_VALUE == 0) return 0.0;
    if (LIGHTING_MODEL_VALUE == 1) return PhongTerm(n, v, l, uPhongExponent);
    return BlinnPhongTerm(n, HalfVector(l, v), uBlinnExponent);
}

// One light: radiance·atten·(albedo·D + Specularity·specMask·S) for the toon mode (header).
vec3 ShadeLight(vec3 n, vec3 v, vec3 l, vec3 radiance, float atten, vec3 albedo,
                float specMask) {
    float ndotl = dot(n, l);
    float k = SpecularTerm(n, v, l);
    vec3 diffuse;
    float spec;
    if (LIGHTING_TOON_VALUE == 1) {
        diffuse = albedo * FlatDiffuse(ndotl, uSmoothness);
        spec = FlatEdge(k, uSmoothness);
    } else if (LIGHTING_TOON_VALUE == 2) {
        float level = uSteppedRepository ? SteppedRepository(clamp(ndotl, 0.0, 1.0) * atten)
                                         : SteppedDocument(RemappedNdotL(ndotl));
        diffuse = albedo * level;
        spec = SteppedSpecular(k, uSmoothness);
    } else if (LIGHTING_TOON_VALUE == 3) {
        diffuse = albedo * RampColor(ndotl);
        spec = k;
    } else {
        diffuse = albedo * LambertTerm(n, l);
        spec = k;
    }
    return radiance * atten * (diffuse + uSpecularity * specMask * spec);
}

// f(t) of the header and the emission factor 1 − Flickering·f(t).
float FlickerWave(float t) {
    return 0.5 + 0.25 * sin(TWO_PI * 1.3 * t) + 0.15 * sin(TWO_PI * 3.7 * t + 1.1)
           + 0.1 * sin(TWO_PI * 7.9 * t + 2.3);
}
float FlickerFactor(float t, float amount) {
    return 1.0 - clamp(amount, 0.0, 1.0) * clamp(FlickerWave(t), 0.0, 1.0);
}

// The point attenuation (saturate(1 − (d/R)²))², 1 for R ≤ 0.
float PointAttenuation(float d, float range) {
    if (range <= 0.0) return 1.0;
    float x = clamp(1.0 - (d / range) * (d / range), 0.0, 1.0);
    return x * x;
}

// The spot's cone factor: 0 outside the outer cosine, 1 inside the inner one.
float SpotCone(float cosAngle, vec2 cosInnerOuter) {
    float inner = cosInnerOuter.x, outer = cosInnerOuter.y;
    float t = clamp((cosAngle - outer) / max(inner - outer, 1e-6), 0.0, 1.0);
    return t * t * (3.0 - 2.0 * t);
}

// ForwardBase: the ambient, the directional light (its shadow visibility sunVisibility, 1 lit,
// 0 in full shadow, enters as the light's attenuation — so the repository's Stepped thresholds
// see the shadow, as Unity's LIGHT_ATTENUATION does), the rim and the emission, once.
vec3 ShadeForwardBaseShadowed(vec3 n, vec3 v, vec3 albedo, float specMask, float emissionMask,
                              float sunVisibility) {
    vec3 c = uAmbient * albedo;
    c += ShadeLight(n, v, SafeNormalize(uSunDir, vec3(0.0, 1.0, 0.0)), uSunRadiance,
                    clamp(sunVisibility, 0.0, 1.0), albedo, specMask);
    if (uRim) c += uRimColor * RimTerm(n, v, uRimPower);
    c += uEmissionColor * emissionMask * FlickerFactor(uTime, uFlicker);
    return c;
}
vec3 ShadeForwardBase(vec3 n, vec3 v, vec3 albedo, float specMask, float emissionMask) {
    return ShadeForwardBaseShadowed(n, v, albedo, specMask, emissionMask, 1.0);
}

// ForwardAdd: every further light (the point lights, then the spot), each added.
vec3 ShadeForwardAdd(vec3 p, vec3 n, vec3 v, vec3 albedo, float specMask) {
    vec3 c = vec3(0.0);
    int count = clamp(uPointCount, 0, 4);
    for (int i = 0; i < 4; ++i) {
        if (i >= count) break;
        vec3 d = uPointPos[i] - p;
        vec3 l = SafeNormalize(d, n);
        c += ShadeLight(n, v, l, uPointRadiance[i], PointAttenuation(length(d), uPointRange[i]),
                        albedo, specMask);
    }
    if (uSpotOn) {
        vec3 d = uSpotPos - p;
        vec3 l = SafeNormalize(d, n);
        float cone = SpotCone(dot(-l, SafeNormalize(uSpotDir, vec3(0.0, -1.0, 0.0))), uSpotCos);
        c += ShadeLight(n, v, l, uSpotRadiance, cone * PointAttenuation(length(d), uSpotRange),
                        albedo, specMask);
    }
    return c;
}

// The whole surface: ForwardBase plus ForwardAdd (the sum Unity's blended passes make).
vec3 ShadeSurface(vec3 p, vec3 n, vec3 v, vec3 albedo, float specMask, float emissionMask) {
    return ShadeForwardBase(n, v, albedo, specMask, emissionMask)
           + ShadeForwardAdd(p, n, v, albedo, specMask);
}
// The same with the sun's shadow visibility (the point lights and the spot cast none).
vec3 ShadeSurfaceShadowed(vec3 p, vec3 n, vec3 v, vec3 albedo, float specMask,
                          float emissionMask, float sunVisibility) {
    return ShadeForwardBaseShadowed(n, v, albedo, specMask, emissionMask, sunVisibility)
           + ShadeForwardAdd(p, n, v, albedo, specMask);
}
