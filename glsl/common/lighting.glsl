// =============================================================================================
// Lighting and toon models of the toon-village thesis (spec/003 §2.1, spec/003 §2.12): Lambert,
// Phong, Blinn–Phong and rim light; the CelShader's toon modes (None, Flat, Stepped, Ramp) and
// the ComplexCelShader's masks; Unity's forward passes summed in one. Used by the shading lab's
// surface.vert (Gouraud: lit per vertex) and surface.frag (per fragment), and by the village,
// which passes the sun's shadow visibility (ShadeSurfaceShadowed). Its @param uniforms belong to
// the group of the effect whose program includes it (shading.toon, village.toon, ...). All
// directions are world-space unit vectors: n the normal, v toward the camera, l toward the light.
// Failure cases guarded: no normalisation of a possibly zero vector, no pow of a negative base
// or to a zero exponent, no smoothstep with equal edges; each function says which it meets.
// Numpy twin: app/sim/lighting.py (snake-case names; tests/unit/test_lighting.py,
// tests/gl/test_shading_lighting.py).
// =============================================================================================
#include "math.glsl"
#include "staircase.glsl"

// ---- the model and toon choices (parameters of the shading group) ---------------------------
// The lighting model: Blinn–Phong is the thesis's choice. Figures: Phong's shininess n 60 and
// 200 (Fig. 18), Blinn–Phong's exponent m 120 and 400 (Fig. 20), the rim exponent 2 (Fig. 22).
// The rim light (1 − max(0, n·v))^m is added as a colour. Toon is the CelShader's Toon popup.
uniform int uLightingModel; // @param 2 [0, 2] step=1 §2.1 lighting model: 0 Lambert, 1 Phong, 2
                            // Blinn–Phong (the thesis's choice)
uniform float uPhongExponent; // @param 60 [1, 500] step=1 §2.1 Phong shininess n of (r·v)^n (Fig.
                              // 18 shows 60 and 200)
uniform float uBlinnExponent; // @param 120 [1, 1000] step=1 §2.1 Blinn–Phong exponent m of (n·h)^m
                              // (Fig. 20 shows 120 and 400)
uniform bool uRim; // @param false §2.1 rim light (1 − max(0, n·v))^m added as a colour
uniform float uRimPower; // @param 2 [0.1, 16] step=0.1 §2.1 rim exponent m (Fig. 22 shows 2)
uniform vec3 uRimColor; // @param (1, 1, 1) [0, 1] color §2.1 rim colour (added)
uniform int uToon; // @param 0 [0, 3] step=1 §2.12 CelShader Toon: 0 None, 1 Flat, 2 Stepped, 3 Ramp
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
uniform bool uSteppedRepository; // @param false §2.12 Stepped with the public repository's
                                 // thresholds (saturate(n·l)·atten: 0, 0.15, 0.30) instead of the
                                 // document's (remapped n·l: 0.45, 0.55, 0.65)
uniform float uSpecularity; // @param 0.168 [0, 1] step=0.001 §2.12 Specularity: weight of the
                            // specular (Fig. 130b shows 0.168)
uniform float uSmoothness; // @param 0.841 [0, 1] step=0.001 §2.12 Smoothness: 1 hard Flat/Stepped
                           // edges, lower softer (Fig. 130b shows 0.841)
uniform vec3 uEmissionColor; // @param (1, 0.75, 0.35) [0, 4] color §2.12 Emission Color where the
                             // Emission (R) mask is set
uniform float uFlicker; // @param 0 [0, 1] step=0.01 §2.12 Flickering: depth of the emission's time
                        // variation (0 steady)

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
// A program compiled with LIGHTING_SPOT defined 0 has no spot light (uSpotOn reads false): a scene
// without one does not pay for its code on a software rasteriser.
#ifdef LIGHTING_SPOT
#define LIGHTING_SPOT_ON (LIGHTING_SPOT != 0 && uSpotOn)
#else
#define LIGHTING_SPOT_ON uSpotOn
#endif

const float SPEC_MIN_EXPONENT = 1e-3;   // the smallest exponent pow sees (never 0)
const float FLAT_DARK = 0.25;           // Flat's unlit level (the repository's)
const float FLAT_RISE = 0.75;           // Flat's lit level 1 minus FLAT_DARK
const float FLAT_HALF_WIDTH = 0.25;     // Flat's edge half-width at Smoothness 0, in x
const float EDGE_WIDTH_MIN = 1e-6;      // floor of an edge's width (width 0: the hard cut)
const float STEPPED_SPEC_GAIN = 4.0;    // Stepped's specular input saturate(4 k − 1.5)
const float STEPPED_SPEC_OFFSET = 1.5;
const float STEPPED_SPEC_STEP = 0.25;   // the staircase's step height
const float STEPPED_SPEC_SOFT = 0.1;    // its softness at Smoothness 0
const float RAMP_ROW_V = 0.5;           // v of the ramp texture's one row (its texel centre)
const float FLICKER_MEAN = 0.5;         // f(t)'s mean; the sines: amplitude, Hz, phase (rad)
const float FLICKER_A1 = 0.25, FLICKER_HZ1 = 1.3;
const float FLICKER_A2 = 0.15, FLICKER_HZ2 = 3.7, FLICKER_PHASE2 = 1.1;
const float FLICKER_A3 = 0.1, FLICKER_HZ3 = 7.9, FLICKER_PHASE3 = 2.3;
const float CONE_WIDTH_MIN = 1e-6;      // floor of inner − outer cosine (equal cones)
const int POINT_LIGHTS_MAX = 4;         // the size of the uPoint* arrays

// Lambert's diffuse term k_diff = max(0, n·l) (spec/003 §2.1), in [0,1]; facing away gives 0.
float LambertTerm(vec3 n, vec3 l) { return max(dot(n, l), 0.0); }

// spec/003 eq. 2.1: the half vector h = (l + v)/‖l + v‖. Failure case: the light exactly
// behind the surface from the camera (l = −v) has no bisector: h = 0, so no highlight.
vec3 HalfVector(vec3 l, vec3 v) { return SafeNormalize(l + v, vec3(0.0)); }

// spec/003 eq. 2.2: Blinn–Phong's k_spec = max(0, n·h)^m, in [0,1]; the base is clamped at 0
// and the exponent at SPEC_MIN_EXPONENT, so pow stays defined.
float BlinnPhongTerm(vec3 n, vec3 h, float m) {
    return pow(max(dot(n, h), 0.0), max(m, SPEC_MIN_EXPONENT));
}

// Phong's k_spec = max(0, r·v)^n, r the mirror of l about n (spec/003 §2.1), in [0,1]; pow's
// base and exponent guarded as in BlinnPhongTerm.
float PhongTerm(vec3 n, vec3 v, vec3 l, float e) {
    vec3 r = reflect(-l, n);
    return pow(max(dot(r, v), 0.0), max(e, SPEC_MIN_EXPONENT));
}

// The rim term k_rim = (1 − max(0, n·v))^m (spec/003 §2.1), in [0,1], largest where the
// surface turns away from the camera; the exponent is floored at SPEC_MIN_EXPONENT.
float RimTerm(vec3 n, vec3 v, float m) {
    return pow(1.0 - max(dot(n, v), 0.0), max(m, SPEC_MIN_EXPONENT));
}

// spec/003 eq. 8.1: the remapped n·l, x = ½(n·l) + ½, from [−1,1] to [0,1] (0 at n·l = −1):
// the coordinate of the Stepped table and of the ramp.
float RemappedNdotL(float ndotl) { return 0.5 * ndotl + 0.5; }

// The document's Stepped table on the remapped n·l x (spec/003 §2.12), the thesis's numbers as
// printed: ≤ 0.45 → 0.2, ≤ 0.55 → 0.5, ≤ 0.65 → 0.7, else 1.0 (cuts at n·l = −0.1, 0.1, 0.3;
// each bound in the band below it). The floor 0.2 is the thesis's built-in ambient.
float SteppedDocument(float x) {
    return x <= 0.45 ? 0.2 : (x <= 0.55 ? 0.5 : (x <= 0.65 ? 0.7 : 1.0));
}

// The public repository's Stepped table (spec/003 Appendix A) on y = saturate(n·l)·atten:
// ≤ 0 → 0.2, ≤ 0.15 → 0.5, ≤ 0.30 → 0.7, else 1.0. It differs from the document's for n·l in
// (−0.1, 0] (0.5 against 0.2) and (0.1, 0.15] (0.7 against 0.5).
float SteppedRepository(float y) {
    return y <= 0.0 ? 0.2 : (y <= 0.15 ? 0.5 : (y <= 0.30 ? 0.7 : 1.0));
}

// Flat's edge E(y) = smoothstep(½ − w, ½ + w, y), w = 0.25·(1 − Smoothness), in [0,1]:
// Smoothness 1 is the hard edge (two levels), lower values soften it (Fig. 127b shows 1, 0.75,
// 0.5). Failure case: written out, with the width floored at EDGE_WIDTH_MIN, because GLSL's
// smoothstep is undefined for equal edges (w = 0).
float FlatEdge(float y, float smoothness) {
    float w = FLAT_HALF_WIDTH * (1.0 - clamp(smoothness, 0.0, 1.0));
    float t = clamp((y - (0.5 - w)) / max(2.0 * w, EDGE_WIDTH_MIN), 0.0, 1.0);
    return t * t * (3.0 - 2.0 * t);
}

// Flat's diffuse level 0.25 + 0.75·E(x) of the remapped n·l x (spec/003 §2.12): one cut at the
// terminator (n·l = 0, the document's), in [0.25, 1]. The levels and the edge's form are the
// public repository's (spec/003 Appendix A); Flat's specular is E(k_spec), hard-edged too.
float FlatDiffuse(float ndotl, float smoothness) {
    return FLAT_DARK + FLAT_RISE * FlatEdge(RemappedNdotL(ndotl), smoothness);
}

// Stepped's specular: the repository's soft staircase SoftStairedValue(saturate(4k − 1.5),
// 0.25, 0.1·(1 − Smoothness)) of staircase.glsl, k the lighting model's k_spec in [0,1].
float SteppedSpecular(float k, float smoothness) {
    return SoftStairedValue(clamp(STEPPED_SPEC_GAIN * k - STEPPED_SPEC_OFFSET, 0.0, 1.0),
                            STEPPED_SPEC_STEP,
                            STEPPED_SPEC_SOFT * (1.0 - clamp(smoothness, 0.0, 1.0)));
}

// Toon = Ramp's colour: the W × 1 ramp texture uRamp at the remapped n·l (RemappedNdotL),
// linear colour. Failure case: read with textureLod, which the vertex stage (Gouraud) allows.
vec3 RampColor(float ndotl) {
    return textureLod(uRamp, vec2(clamp(RemappedNdotL(ndotl), 0.0, 1.0), RAMP_ROW_V), 0.0).rgb;
}

// The lighting model's specular term k_spec in [0,1] (0 Lambert: none, 1 Phong, 2 Blinn–Phong).
// Failure case: 0 where n·l ≤ 0, so no highlight leaks through the terminator onto the unlit
// side (Phong's r·v > 0 there; Blinn–Phong's n·h avoids it only in part).
float SpecularTerm(vec3 n, vec3 v, vec3 l) {
    if (dot(n, l) <= 0.0 || LIGHTING_MODEL_VALUE == 0) return 0.0;
    if (LIGHTING_MODEL_VALUE == 1) return PhongTerm(n, v, l, uPhongExponent);
    return BlinnPhongTerm(n, HalfVector(l, v), uBlinnExponent);
}

// One light, in linear radiance: radiance·atten·(albedo·D + Specularity·specMask·S), D and S
// the toon mode's diffuse level and specular (0 None: max(0, n·l) and k_spec; 1 Flat; 2 Stepped;
// 3 Ramp: the ramp's colour and k_spec). atten ([0,1]) is the light's distance, cone and shadow
// factor, kept apart from radiance because the repository's Stepped thresholds see it. The
// specular's colour is the light's; specMask is the Specular (G) mask of the ComplexCelShader.
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

// The emission's flicker, t in seconds: f(t) = ½ + ¼ sin(2π·1.3t) + 0.15 sin(2π·3.7t + 1.1)
// + 0.1 sin(2π·7.9t + 2.3), in [0,1]: three incommensurate sines, a candle-like irregular
// flicker. The thesis names Flickering a time-varying intensity only, so the function is ours.
float FlickerWave(float t) {
    return FLICKER_MEAN + FLICKER_A1 * sin(TWO_PI * FLICKER_HZ1 * t)
           + FLICKER_A2 * sin(TWO_PI * FLICKER_HZ2 * t + FLICKER_PHASE2)
           + FLICKER_A3 * sin(TWO_PI * FLICKER_HZ3 * t + FLICKER_PHASE3);
}
// The emission's factor 1 − Flickering·f(t), in [0,1]: with Flickering 0 an emissive pixel is
// exactly uEmissionColor, light or no light.
float FlickerFactor(float t, float amount) {
    return 1.0 - clamp(amount, 0.0, 1.0) * clamp(FlickerWave(t), 0.0, 1.0);
}

// The point attenuation (saturate(1 − (d/R)²))² at distance d from the light (metres), 1 at the
// light and 0 at its range R; beyond the thesis, which uses Unity's. No inverse square, so it
// stays finite at d = 0; R ≤ 0 means no falloff (1).
float PointAttenuation(float d, float range) {
    if (range <= 0.0) return 1.0;
    float x = clamp(1.0 - (d / range) * (d / range), 0.0, 1.0);
    return x * x;
}

// The spot's cone factor smoothstep(cos_outer, cos_inner, cos angle) to its axis: 0 outside the
// outer cosine, 1 inside the inner one. Failure case: written out, with inner − outer floored
// at CONE_WIDTH_MIN, because GLSL's smoothstep is undefined for equal edges.
float SpotCone(float cosAngle, vec2 cosInnerOuter) {
    float inner = cosInnerOuter.x, outer = cosInnerOuter.y;
    float t = clamp((cosAngle - outer) / max(inner - outer, CONE_WIDTH_MIN), 0.0, 1.0);
    return t * t * (3.0 - 2.0 * t);
}

// Unity's ForwardBase pass (spec/003 §0, §1), in linear radiance: uAmbient·albedo, the
// directional light, the rim (added as a colour) and the emission uEmissionColor·R·flicker(t),
// once. The sun's shadow visibility sunVisibility (1 lit, 0 in full shadow) enters as the light's
// attenuation, so the repository's Stepped thresholds see the shadow as Unity's
// LIGHT_ATTENUATION does. Failure case: a zero uSunDir falls back to straight up.
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

// Unity's ForwardAdd passes, one per further light, blended One One: Σ ShadeLight(point i) +
// ShadeLight(spot) at p (metres), in linear radiance. Failure cases: uPointCount is clamped to
// [0, 4]; a light exactly at the surface gives l = n; a zero spot axis falls back to down.
// The spot's factor is its cone times PointAttenuation over uSpotRange.
vec3 ShadeForwardAdd(vec3 p, vec3 n, vec3 v, vec3 albedo, float specMask) {
    vec3 c = vec3(0.0);
    int count = clamp(uPointCount, 0, POINT_LIGHTS_MAX);
    for (int i = 0; i < POINT_LIGHTS_MAX; ++i) {
        if (i >= count) break;
        vec3 d = uPointPos[i] - p;
        vec3 l = SafeNormalize(d, n);
        c += ShadeLight(n, v, l, uPointRadiance[i], PointAttenuation(length(d), uPointRange[i]),
                        albedo, specMask);
    }
    if (LIGHTING_SPOT_ON) {
        vec3 d = uSpotPos - p;
        vec3 l = SafeNormalize(d, n);
        float cone = SpotCone(dot(-l, SafeNormalize(uSpotDir, vec3(0.0, -1.0, 0.0))), uSpotCos);
        c += ShadeLight(n, v, l, uSpotRadiance, cone * PointAttenuation(length(d), uSpotRange),
                        albedo, specMask);
    }
    return c;
}

// The whole surface, in linear radiance: ForwardBase plus ForwardAdd, the same sum Unity's
// blended passes make, here in one pass.
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
