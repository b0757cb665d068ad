// =============================================================================================
// The toon village's water, the thesis's Custom/Nature/Water (spec/003 §2.10, its §7.2): the
// functions water.vert, water.frag and underwater.frag share (and the probe
// glsl/tests/toon_water_probe.frag evaluates), and the @param uniforms of Fig. 115 (group
// toon_water). Numpy twin: app/sim/toon_water.py (same names in snake case).
//
//   ScreenUV          fragment → screen coordinates of the grab and of the depth textures, the
//                     one place the render-texture flip lives (uFlipY; off in GL, see below)
//   TideLevel         sea level + Tide Height·sin t (the repository's _TideHeight·_SinTime.w
//                     along the plane's normal +y)
//   WaveUVs           the one normal map sampled twice (crossing waves): uv = (x, −z)/tile;
//                     (uv + s)·Wave Scale and uv − s, s = Water Speed·t/20 (Unity's _Time.x;
//                     the repository's coordinates and speeds)
//   WaveNormal        the two texels averaged, n.xy = 2·tex − 1 (spec/003 eq. 3.1) times Wave
//                     Intensity, z = 1 − ½(x² + y²) (spec/003 eq. 3.4, the repository's unpack),
//                     carried to world (t = +x, b = −z, n = +y) and normalised
//   RefractionOffset  the grab's distortion, Wave Intensity·0.025·n.xz (the repository's)
//   ViewDepth         window depth → metres along the camera's axis (perspective, GL depth range)
//   FogWeight*        the depth fog's weight w of lerp(refraction, colour, w):
//                       document    w = saturate(d·I), d the raw depth texture value (0 at the
//                                   near plane, 1 at the far) — the document's
//                                   lerp(refraction, waterColor, depth) with Water Fog Intensity I
//                       repository  w = saturate(z/far·I·31) (Linear01Depth·fogInt·factor,
//                                   factor = 1 + 30 in play); with Refraction ½ it is the
//                                   repository's lerp(refr, color, 0.5 + 0.5·saturate(…))
//                       thickness   w = 1 − exp(−I·L), L the water's thickness along the view
//                                   ray in metres from the two linearised depths (beyond the
//                                   thesis: I read as an extinction per metre)
//   WaterRefraction   mix(mix(colour, refraction, α), colour, w): α = Refraction (the repository's
//                     lerp(color, refraction, 0.5) without fog; α = 1 and the document's fog
//                     give lerp(refraction, waterColor, depth) exactly)
//   SimpleBand        the Simple type's v·n with the perturbed normal in 3 bands:
//                     StairedValue(1 − saturate(n·v), 1/3) ∈ {0, ½, 1} (spec/003 eq. 7.18,
//                     spec/003 eq. 7.19, spec/003 eq. 7.20 with step_x = 1/3)
//   ToonReflection    the Complex type's reflection discretised per channel with Toon Value
//                     (spec/003 eq. 7.18, spec/003 eq. 7.19, spec/003 eq. 7.20)
//   FresnelWaterPow5  F(u) = 0.018 + 0.982·(1 − u)^5, u = cos θ = n·v (spec/003 eq. 7.21,
//                     spec/003 eq. 7.22: Schlick for air → water, n = 1.31)
//   FresnelWaterRamp  the same read from the ramp texture baked from it (the thesis's Fig. 110),
//                     sampled at texel-centre coordinates so u = 0 and u = 1 hit its end texels
//   ToonHighlight     beyond the thesis: the main light's Blinn–Phong highlight (spec/003 eq. 2.1,
//                     spec/003 eq. 2.2) discretised like the rest (StairedValue)
//   WaterLight        the water's colour lit: Lambert of the flat plane by the main light plus
//                     the sky's ambient (spec/003 §2.1)
//
// The flip (spec/003 §2.10): Unity's render textures may be upside down, so the thesis flips
// the depth texture's coordinates with _ProjectionParams and keeps separate coordinates for the
// grab and the depth. In GL the copy of the colour and of the depth come from one framebuffer
// and share its origin (bottom-left), so both lookups go through ScreenUV and uFlipY stays off;
// on, it flips both (tests/gl/test_toon_water.py shows both facts).
//
// Failure cases guarded: the reflected direction pushed back above the horizon (a wave normal
// can reflect the view ray downward, into the sky cubemap's sea); n·v and u clamped into [0, 1]
// before the Fresnel and the bands; the view depth's denominator kept positive for d = 1 (the
// cleared far plane: z = far); a thickness below zero (the distorted sample in front of the
// water) read as 0; the exponentials' arguments bounded; a zero view or half vector falls back
// (SafeNormalize); the light below the horizon gives no highlight and no direct light.
// =============================================================================================
#include "math.glsl"
#include "staircase.glsl"
#include "fresnel.glsl"

// ---- Fig. 115's properties (spec/003 §2.10), ranges from the public repository -------------
uniform vec3 uColor;              // @param (0.05, 0.3, 0.36) [0, 8] color §2.10 Color (HDR): the water's base colour, lit by the main light and the sky's ambient (Fig. 115 shows no value; the repository's default white is a placeholder)
uniform float uWaveIntensity;     // @param 0.4 [0, 1] step=0.01 §2.10 Wave Intensity: scales the normal map's x and y and the grab's distortion (no value shown in Fig. 115; the repository's range starts at 0.05, here at 0: flat water)
uniform float uWaveScale;         // @param 1 [1, 10] step=0.1 §2.10 Wave Scale: multiplies the first sample's normal-map coordinates (repository default 1)
uniform bool uDepthFog;           // @param true §2.10 Depth Fog?: the water colour hides what is deep or far below it (ticked in Fig. 115)
uniform float uWaterFogIntensity; // @param 0.535 [0, 1] step=0.001 §2.10 Water Fog Intensity (Fig. 115 shows 0.535); the thickness method reads it per metre
uniform float uWaterSpeed;        // @param 0.089 [0.01, 0.25] step=0.001 §2.10 Water Speed: added to the normal map's coordinates, times Unity's _Time.x = t/20 (Fig. 115 shows 0.089)
uniform float uTideHeight;        // @param 0.3 [0, 20] step=0.01 unit=m §2.10 Tide Height: the plane moves along its normal by this times sin t (Fig. 115 shows 0.3)
uniform float uToonValue;         // @param 0.128 [0.01, 0.2] step=0.001 §2.10 Toon Value: step_x of the reflection's staircase, larger is coarser (Fig. 115 shows about 0.128)
// ---- beyond Fig. 115 -------------------------------------------------------------------------
uniform float uRefraction;        // @param 1 [0, 1] step=0.01 §2.10 share α of the refraction in the unfogged water, mix(colour, refraction, α): 1 the document's lerp(refraction, waterColor, depth), a transparent plane without fog (Fig. 113b); the repository's is a fixed 0.5
uniform bool uReflectionTint;     // @param true §2.10 Complex: the reflection lerped 20 % toward the lit water colour (the repository's; the document does not say)
uniform float uBandStrength;      // @param 0.35 [0, 2] step=0.01 §2.10 Simple: how much light each of the 3 bands of v·n adds (0, ½, 1 of it toward grazing views)
uniform float uHighlight;         // @param 1 [0, 4] step=0.01 §2.10 the main light's toon highlight (sun by day, moon by night; beyond the thesis), 0 off
uniform float uHighlightExponent; // @param 600 [1, 4000] step=1 §2.10 the highlight's Blinn–Phong exponent m of (n·h)^m
uniform float uWaveTile;          // @param 12 [1, 200] step=0.5 unit=m §2.10 metres of water one tile of the normal map covers at Wave Scale 1 (Unity's plane UVs)
uniform bool uFlipY;              // @param false §2.10 flip the screen coordinates of the grab and depth lookups (Unity's render-texture flip; GL needs none)
uniform int uOutput;              // @param 0 [0, 4] step=1 §2.10 show: 0 the water, 1 its reflection, 2 its refraction (fogged), 3 the reflectance (Complex) or the band (Simple), 4 the depth fog's weight

//: the Fresnel reflectance of air → water at normal incidence, ((1 − 1.31)/(1 + 1.31))², as the
//: thesis rounds it in spec/003 eq. 7.22
const float WATER_F0 = 0.018;
//: the repository's screen-space distortion per unit of Wave Intensity·n.xz
const float REFRACTION_DISTORTION = 0.025;
//: the repository's Linear01Depth factor in play (1 + 30; 1 + 3000 in Unity's editor camera)
const float REPOSITORY_FOG_FACTOR = 31.0;
//: Unity's _Time.x is t/20
const float UNITY_TIME_X = 0.05;
//: the repository's reflection lookup: SampleLightProbeCubemap(r, 0.025), LOD 0.025·6
const float REFLECTION_LOD = 0.15;

// The screen coordinates of a fragment (or of a distorted fragment position) in the grab and
// depth textures: fragCoord/viewport, y flipped when flipY (spec/003 §2.10's render-texture
// flip; in GL both textures share the framebuffer's origin, so it stays off).
vec2 ScreenUV(vec2 fragCoord, vec2 viewport, bool flipY) {
    vec2 uv = fragCoord / max(viewport, vec2(1.0));
    return flipY ? vec2(uv.x, 1.0 - uv.y) : uv;
}

// The plane's height at time t: sea level + Tide Height·sin t along its normal (+y).
float TideLevel(float seaLevel, float tideHeight, float t) {
    return seaLevel + tideHeight * sin(t);
}

// The two coordinates of the one normal map (crossing waves): (uv + s)·scale and uv − s.
void WaveUVs(vec2 worldXZ, float t, float tile, float scale, float speed, out vec2 uv1,
             out vec2 uv2) {
    vec2 uv = vec2(worldXZ.x, -worldXZ.y) / max(tile, 1e-3);
    float s = speed * t * UNITY_TIME_X;
    uv1 = (uv + s) * scale;
    uv2 = uv - s;
}

// The perturbed world normal from the two texels of the normal map (stored 0.5·n + 0.5):
// spec/003 eq. 3.1 on their average, x and y scaled by Wave Intensity, spec/003 eq. 3.4's z;
// tangent +x, bitangent −z (v grows northward), normal +y.
vec3 WaveNormal(vec4 tex1, vec4 tex2, float intensity) {
    vec2 xy = (2.0 * (0.5 * (tex1.rg + tex2.rg)) - 1.0) * intensity;  // spec/003 eq. 3.1
    float z = max(1.0 - 0.5 * dot(xy, xy), 0.0);                       // spec/003 eq. 3.4
    return SafeNormalize(vec3(xy.x, z, -xy.y), vec3(0.0, 1.0, 0.0));
}

// The grab's distortion in screen coordinates: Wave Intensity·0.025·n.xz.
vec2 RefractionOffset(vec3 n, float intensity) {
    return intensity * REFRACTION_DISTORTION * n.xz;
}

// Metres along the camera's axis of a window depth d (GL's perspective projection, depth range
// [0, 1]): z = 2nf/(f + n − (2d − 1)(f − n)) = nf/(f·(1 − d) + n·d), the second form in
// float32 (1 − d is exact near the far plane, where f − d·(f − n) cancels); d = 1 gives f.
float ViewDepth(float d, vec2 nearFar) {
    float n = nearFar.x, f = nearFar.y;
    float dd = clamp(d, 0.0, 1.0);
    return n * f / max(f * (1.0 - dd) + n * dd, 1e-12);
}

// The document's depth fog weight: the raw depth texture value times Water Fog Intensity.
float FogWeightDocument(float rawDepth, float intensity) {
    return saturate(rawDepth * intensity);
}

// The repository's: saturate(Linear01Depth·fogInt·31) (its "0.5 + 0.5·" is Refraction ½).
float FogWeightRepository(float linear01, float intensity) {
    return saturate(linear01 * intensity * REPOSITORY_FOG_FACTOR);
}

// Beyond the thesis: 1 − exp(−I·L) of the water's thickness L (metres) along the view ray.
float FogWeightThickness(float metres, float intensity) {
    return 1.0 - exp(-clamp(intensity * max(metres, 0.0), 0.0, 80.0));
}

// What the water shows of what lies beneath it: mix(mix(colour, refraction, α), colour, w).
vec3 WaterRefraction(vec3 refraction, vec3 colour, float alpha, float w) {
    return mix(mix(colour, refraction, clamp(alpha, 0.0, 1.0)), colour, clamp(w, 0.0, 1.0));
}

// The Simple type's v·n in 3 bands (spec/003 eq. 7.18, spec/003 eq. 7.19, spec/003 eq. 7.20,
// step_x = 1/3): 0 looking down, ½, then 1 toward grazing views.
float SimpleBand(float nDotV) {
    return StairedValue(1.0 - saturate(nDotV), 1.0 / 3.0);
}

// The Complex type's reflection discretised per channel with Toon Value (spec/003 eq. 7.18,
// spec/003 eq. 7.19, spec/003 eq. 7.20).
vec3 ToonReflection(vec3 reflection, float toonValue) {
    return StairedValue(max(reflection, vec3(0.0)), toonValue);
}

// The view ray reflected by the wave normal, kept above the horizon (its |y|).
vec3 ReflectionDirection(vec3 v, vec3 n) {
    vec3 r = reflect(-v, n);
    return SafeNormalize(vec3(r.x, abs(r.y), r.z), vec3(0.0, 1.0, 0.0));
}

// spec/003 eq. 7.21 and spec/003 eq. 7.22: u = cos θ = n·v, F = 0.018 + 0.982·(1 − u)^5.
float FresnelWaterPow5(float u) {
    return SchlickFresnel(WATER_F0, u);
}

// spec/003 eq. 7.21 and spec/003 eq. 7.22 read from the ramp texture (W × 1, texel i holding F at
// u = i/(W − 1)): the coordinate (u·(W − 1) + ½)/W lands on texel centres at both ends.
float FresnelWaterRamp(sampler2D ramp, float u) {
    float w = float(textureSize(ramp, 0).x);
    float s = (clamp(u, 0.0, 1.0) * (w - 1.0) + 0.5) / w;
    return texture(ramp, vec2(s, 0.5)).r;
}

// Beyond the thesis: the main light's highlight on the waves, h = (l + v)/‖l + v‖
// (spec/003 eq. 2.1), k = (n·h)^m (spec/003 eq. 2.2), staired with step_x like the rest; none
// with the light below the horizon.
float ToonHighlight(vec3 n, vec3 v, vec3 l, float exponent, float stepX) {
    if (l.y <= 0.0) return 0.0;
    vec3 h = SafeNormalize(l + v, n);
    float k = pow(max(dot(n, h), 0.0), max(exponent, 1.0));
    return StairedValue(k, stepX);
}

// The water's colour lit as a Lambert surface of the flat plane (normal +y) by the main light,
// plus the sky's ambient (spec/003 §2.1).
vec3 WaterLight(vec3 colour, vec3 l, vec3 radiance, vec3 ambient) {
    return colour * (radiance * max(l.y, 0.0) + ambient);
}
