// The toon village's water, the thesis's Custom/Nature/Water (spec/003 §2.10, its §7.2): the
// functions water.vert, water.frag and underwater.frag share (and the probe
// glsl/tests/toon_water_probe.frag evaluates), and the @param uniforms of Fig. 115 (group
// toon_water). Numpy twin: app/sim/toon_water.py (same names in snake case). It computes the
// tide, the crossing waves' normal, the grab's distortion, the depth fog, the refraction mix,
// the toon bands and reflection, Schlick's Fresnel, the highlight and the lit water colour.
// Failure cases guarded (each at its function): a reflection pushed below the horizon, n·v and
// u outside [0, 1], the far plane's depth (d = 1), a negative water thickness, unbounded
// exponentials, zero view or half vectors, and a light below the horizon.
#include "math.glsl"
#include "staircase.glsl"
#include "fresnel.glsl"

uniform vec3 uColor; // @param (0.05, 0.3, 0.36) [0, 8] color §2.10 Color (HDR): the water's base
                     // colour, lit by the main light and the sky's ambient (Fig. 115 shows no
                     // value; the repository's default white is a placeholder)
uniform float uWaveIntensity; // @param 0.4 [0, 1] step=0.01 §2.10 Wave Intensity: scales the normal
                              // map's x and y and the grab's distortion (no value shown in Fig.
                              // 115; the repository's range starts at 0.05, here at 0: flat water)
uniform float uWaveScale; // @param 1 [1, 10] step=0.1 §2.10 Wave Scale: multiplies the first
                          // sample's normal-map coordinates (repository default 1)
uniform bool uDepthFog; // @param true §2.10 Depth Fog?: the water colour hides what is deep or far
                        // below it (ticked in Fig. 115)
uniform float uWaterFogIntensity; // @param 0.535 [0, 1] step=0.001 §2.10 Water Fog Intensity (Fig.
                                  // 115 shows 0.535); the thickness method reads it per metre
uniform float uWaterSpeed; // @param 0.089 [0.01, 0.25] step=0.001 §2.10 Water Speed: added to the
                           // normal map's coordinates, times Unity's _Time.x = t/20 (Fig. 115 shows
                           // 0.089)
uniform float uTideHeight; // @param 0.3 [0, 20] step=0.01 unit=m §2.10 Tide Height: the plane moves
                           // along its normal by this times sin t (Fig. 115 shows 0.3)
uniform float uToonValue; // @param 0.128 [0.01, 0.2] step=0.001 §2.10 Toon Value: step_x of the
                          // reflection's staircase, larger is coarser (Fig. 115 shows about 0.128)
// ---- beyond Fig. 115 -------------------------------------------------------------------------
// uRefraction: share α of the refraction in the unfogged water, mix(colour, refraction, α):
// 1 the document's lerp(refraction, waterColor, depth), a transparent plane without fog
// (Fig. 113b); the repository's is a fixed 0.5.
uniform float uRefraction; // @param 1 [0, 1] step=0.01 §2.10 share α of the refraction in the
                           // unfogged water, mix(colour, refraction, α): 1 the document's
                           // lerp(refraction, waterColor, depth), a transparent plane without fog
                           // (Fig. 113b); the repository's is a fixed 0.5
uniform bool uReflectionTint; // @param true §2.10 Complex: the reflection lerped 20 % toward the
                              // lit water colour (the repository's; the document does not say)
uniform float uBandStrength; // @param 0.35 [0, 2] step=0.01 §2.10 Simple: how much light each of
                             // the 3 bands of v·n adds (0, ½, 1 of it toward grazing views)
uniform float uHighlight; // @param 1 [0, 4] step=0.01 §2.10 the main light's toon highlight (sun by
                          // day, moon by night; beyond the thesis), 0 off
uniform float uHighlightExponent; // @param 600 [1, 4000] step=1 §2.10 the highlight's Blinn–Phong
                                  // exponent m of (n·h)^m
uniform float uWaveTile; // @param 12 [1, 200] step=0.5 unit=m §2.10 metres of water one tile of the
                         // normal map covers at Wave Scale 1 (Unity's plane UVs)
uniform bool uFlipY; // @param false §2.10 flip the screen coordinates of the grab and depth lookups
                     // (Unity's render-texture flip; GL needs none)
uniform int uOutput; // @param 0 [0, 4] step=1 §2.10 show: 0 the water, 1 its reflection, 2 its
                     // refraction (fogged), 3 the reflectance (Complex) or the band (Simple), 4 the
                     // depth fog's weight

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

//: the smallest normal-map tile, m (a zero tile would divide by 0)
const float MIN_TILE = 1e-3;
//: the smallest denominator of ViewDepth
const float MIN_DEPTH_DENOMINATOR = 1e-12;
//: the largest optical depth of the thickness fog (e^−80 is 0 in float32; bounds exp)
const float MAX_FOG_DEPTH = 80.0;
//: step_x of the Simple type's three bands
const float SIMPLE_BAND_STEP = 1.0 / 3.0;

// The screen coordinates [0, 1]² of a fragment (or of a distorted fragment position, pixels) in
// the grab and depth textures: fragCoord/viewport, y flipped when flipY. This is the one place
// the render-texture flip lives (spec/003 §2.10): Unity's render textures may be upside down, so
// the thesis flips the depth texture's coordinates with _ProjectionParams and keeps separate
// coordinates for the grab and the depth. In GL the copies of the colour and of the depth come
// from one framebuffer and share its origin (bottom-left), so uFlipY stays off; on, it flips
// both (tests/gl/test_toon_water.py shows both facts). A zero viewport counts as 1 pixel.
vec2 ScreenUV(vec2 fragCoord, vec2 viewport, bool flipY) {
    vec2 uv = fragCoord / max(viewport, vec2(1.0));
    return flipY ? vec2(uv.x, 1.0 - uv.y) : uv;
}

// The plane's height (m) at time t (s): sea level + Tide Height·sin t along its normal (+y),
// the repository's _TideHeight·_SinTime.w.
float TideLevel(float seaLevel, float tideHeight, float t) {
    return seaLevel + tideHeight * sin(t);
}

// The two coordinates of the one normal map (crossing waves): uv = (x, −z)/tile (worldXZ and
// tile in metres), then (uv + s)·scale and uv − s with s = Water Speed·t/20 (Unity's _Time.x;
// the repository's coordinates and speeds). A tile under MIN_TILE is raised to it.
void WaveUVs(vec2 worldXZ, float t, float tile, float scale, float speed, out vec2 uv1,
             out vec2 uv2) {
    vec2 uv = vec2(worldXZ.x, -worldXZ.y) / max(tile, MIN_TILE);
    float s = speed * t * UNITY_TIME_X;
    uv1 = (uv + s) * scale;
    uv2 = uv - s;
}

// The perturbed world normal from the two texels of the normal map (stored 0.5·n + 0.5):
// spec/003 eq. 3.1 on their average, x and y scaled by Wave Intensity, spec/003 eq. 3.4's z;
// tangent +x, bitangent −z (v grows northward), normal +y; the repository's unpack. Result:
// a unit world vector. Failure case: a strong intensity makes x² + y² > 2 (z clamped at 0) and
// a zero vector falls back to +y (SafeNormalize).
vec3 WaveNormal(vec4 tex1, vec4 tex2, float intensity) {
    vec2 xy = (2.0 * (0.5 * (tex1.rg + tex2.rg)) - 1.0) * intensity;  // spec/003 eq. 3.1
    float z = max(1.0 - 0.5 * dot(xy, xy), 0.0);                       // spec/003 eq. 3.4
    return SafeNormalize(vec3(xy.x, z, -xy.y), vec3(0.0, 1.0, 0.0));
}

// The grab's distortion in screen coordinates [0, 1]: Wave Intensity·0.025·n.xz (the
// repository's).
vec2 RefractionOffset(vec3 n, float intensity) {
    return intensity * REFRACTION_DISTORTION * n.xz;
}

// Metres along the camera's axis of a window depth d (GL's perspective projection, depth range
// [0, 1]): z = 2nf/(f + n − (2d − 1)(f − n)) = nf/(f·(1 − d) + n·d), the second form in
// float32 (1 − d is exact near the far plane, where f − d·(f − n) cancels); d = 1 (the cleared
// far plane) gives f. nearFar in metres. Failure case: d outside [0, 1] is clamped and the
// denominator kept positive.
float ViewDepth(float d, vec2 nearFar) {
    float n = nearFar.x, f = nearFar.y;
    float dd = clamp(d, 0.0, 1.0);
    return n * f / max(f * (1.0 - dd) + n * dd, MIN_DEPTH_DENOMINATOR);
}

// The depth fog's weight w [0, 1] of lerp(refraction, colour, w), three ways (uFogMethod).
// The document's: w = saturate(d·I), d the raw depth texture value (0 at the near plane, 1 at
// the far), the document's lerp(refraction, waterColor, depth) with Water Fog Intensity I.
float FogWeightDocument(float rawDepth, float intensity) {
    return saturate(rawDepth * intensity);
}

// The repository's: w = saturate(z/far·I·31), its Linear01Depth·fogInt·factor with factor =
// 1 + 30 in play; with Refraction ½ it is the repository's
// lerp(refr, color, 0.5 + 0.5·saturate(…)).
float FogWeightRepository(float linear01, float intensity) {
    return saturate(linear01 * intensity * REPOSITORY_FOG_FACTOR);
}

// Beyond the thesis: w = 1 − exp(−I·L), L the water's thickness along the view ray in metres
// from the two linearised depths, I read as an extinction per metre. Failure cases: a negative
// thickness (the distorted sample in front of the water) reads as 0; the exponent is bounded.
float FogWeightThickness(float metres, float intensity) {
    return 1.0 - exp(-clamp(intensity * max(metres, 0.0), 0.0, MAX_FOG_DEPTH));
}

// What the water shows of what lies beneath it (linear radiance):
// mix(mix(colour, refraction, α), colour, w) with α = Refraction. α = ½ without fog is the
// repository's lerp(color, refraction, 0.5); α = 1 with the document's fog gives its
// lerp(refraction, waterColor, depth) exactly. α and w are clamped into [0, 1].
vec3 WaterRefraction(vec3 refraction, vec3 colour, float alpha, float w) {
    return mix(mix(colour, refraction, clamp(alpha, 0.0, 1.0)), colour, clamp(w, 0.0, 1.0));
}

// The Simple type's v·n in 3 bands (spec/003 eq. 7.18, spec/003 eq. 7.19, spec/003 eq. 7.20,
// step_x = 1/3), with the perturbed normal: 0 looking down, ½, then 1 toward grazing views.
// n·v is clamped into [0, 1] first.
float SimpleBand(float nDotV) {
    return StairedValue(1.0 - saturate(nDotV), SIMPLE_BAND_STEP);
}

// The Complex type's reflection discretised per channel with Toon Value (spec/003 eq. 7.18,
// spec/003 eq. 7.19, spec/003 eq. 7.20); linear radiance, negatives read as 0.
vec3 ToonReflection(vec3 reflection, float toonValue) {
    return StairedValue(max(reflection, vec3(0.0)), toonValue);
}

// The view ray reflected by the wave normal (unit vectors), kept above the horizon (its |y|):
// a wave normal can reflect the view ray downward, into the sky cubemap's sea. A zero result
// falls back to +y.
vec3 ReflectionDirection(vec3 v, vec3 n) {
    vec3 r = reflect(-v, n);
    return SafeNormalize(vec3(r.x, abs(r.y), r.z), vec3(0.0, 1.0, 0.0));
}

// spec/003 eq. 7.21 and spec/003 eq. 7.22: u = cos θ = n·v, F = 0.018 + 0.982·(1 − u)^5,
// Schlick for air → water (n = 1.31). Reflectance [0, 1]; u is clamped by SchlickFresnel.
float FresnelWaterPow5(float u) {
    return SchlickFresnel(WATER_F0, u);
}

// spec/003 eq. 7.21 and spec/003 eq. 7.22 read from the ramp texture (W × 1, texel i holding F at
// u = i/(W − 1); the thesis's Fig. 110): the coordinate (u·(W − 1) + ½)/W lands on texel
// centres at both ends, so u = 0 and u = 1 read its end texels. u is clamped into [0, 1].
float FresnelWaterRamp(sampler2D ramp, float u) {
    float w = float(textureSize(ramp, 0).x);
    float s = (clamp(u, 0.0, 1.0) * (w - 1.0) + 0.5) / w;
    return texture(ramp, vec2(s, 0.5)).r;
}

// Beyond the thesis: the main light's highlight on the waves, h = (l + v)/‖l + v‖
// (spec/003 eq. 2.1), k = (n·h)^m (spec/003 eq. 2.2), staired with step_x like the rest;
// [0, 1]. Failure cases: none with the light below the horizon; l + v = 0 falls back to n.
float ToonHighlight(vec3 n, vec3 v, vec3 l, float exponent, float stepX) {
    if (l.y <= 0.0) return 0.0;
    vec3 h = SafeNormalize(l + v, n);
    float k = pow(max(dot(n, h), 0.0), max(exponent, 1.0));
    return StairedValue(k, stepX);
}

// The water's colour lit as a Lambert surface of the flat plane (normal +y) by the main light,
// plus the sky's ambient (spec/003 §2.1); linear radiance. A light below the horizon adds no
// direct light.
vec3 WaterLight(vec3 colour, vec3 l, vec3 radiance, vec3 ambient) {
    return colour * (radiance * max(l.y, 0.0) + ambient);
}
