// The three wave models of the maritime thesis, chapter 2 (spec/000 §1.1), behind one interface:
//   OceanDisplacement(off, spacing) → (D_x, η, D_z) [m] at the rest point camera.xz + off;
//   OceanSurface(off, footprint, n, foam, lostMss) → unit normal, foam [0, 1], lost slope variance.
// Models: 0 = sine (§1.1(a)), 1 = Gerstner (§1.1(b)), 2 = FFT (Tessendorf 2001, §1.1(d)–(e)).
// Rest points are relative to the camera and every phase that depends on the absolute position
// is folded on the CPU in float64 (uSinePhase, uGerstnerB.y, uCascadeUV.xy), so float32 holds at
// any distance from the origin.
// Failure cases guarded: k = 0 is never sent (CPU); at most 64 Gerstner waves; folds of the FFT
// surface; waves shorter than the pixel (filtered, their slope variance handed to the glitter);
// the mesh's edge (displacement fades to flat water between uFadeStart and uFadeEnd, so it meets
// the analytic far plane; normals are never faded, only filtered by the footprint).

#include "math.glsl"

uniform int uWaveModel;          // 0 sine, 1 Gerstner, 2 FFT

// Whether the wave model is m. A program compiled for one model (OCEAN_WAVE_MODEL = 0, 1 or 2:
// the passes of app/effects/ocean/surface.py) keeps only that model's code, the others' branches
// being constant-false; without the define, uWaveModel chooses per draw. A software rasteriser
// runs the code of every branch with masks, taken or not: three models cost it all three.
#ifdef OCEAN_WAVE_MODEL
#define OCEAN_MODEL_IS(m) (OCEAN_WAVE_MODEL == (m))
#else
#define OCEAN_MODEL_IS(m) (uWaveModel == (m))
#endif
uniform float uTime;             // seconds
uniform float uFadeStart;        // m: displacement starts fading to flat water here
uniform float uFadeEnd;          // m: and is flat from here on
uniform float uFoamThreshold;    // Jacobian below which the surface foams (Gerstner; FFT bakes it)
uniform float uFoamWidth;        // Jacobian range of the foam ramp

uniform vec4 uSine;              // (D_x, D_z, k, A)
uniform vec2 uSinePhase;         // (ω, φ + k·D·camera.xz mod 2π)

#define MAX_GERSTNER 64
uniform int uGerstnerCount;
uniform vec4 uGerstnerA[MAX_GERSTNER];  // (D_x, D_z, k, A)
uniform vec4 uGerstnerB[MAX_GERSTNER];  // (ω, φ + k·D·camera.xz mod 2π, s = kA, 0)

uniform int uCascades;
// The FFT's cascades in use, and whether cascade i is one of them: fixed when the program is
// built for a count (OCEAN_CASCADES, as for the model above), else uCascades at run time.
#ifdef OCEAN_CASCADES
#define OCEAN_CASCADE_COUNT OCEAN_CASCADES
#else
#define OCEAN_CASCADE_COUNT uCascades
#endif
#define OCEAN_HAS_CASCADE(i) (OCEAN_CASCADE_COUNT > (i))
uniform vec4 uCascadeUV[4];      // (fract(camera.xz / L + ½/N): texel centres, 1/L, N/L)
uniform float uFoamWeight[4];
uniform sampler2D uDisp0;
uniform sampler2D uDisp1;
uniform sampler2D uDisp2;
uniform sampler2D uDisp3;
uniform sampler2D uDeriv0;
uniform sampler2D uDeriv1;
uniform sampler2D uDeriv2;
uniform sampler2D uDeriv3;
uniform sampler2D uFoam0;
uniform sampler2D uFoam1;
uniform sampler2D uFoam2;
uniform sampler2D uFoam3;


const float MIN_LENGTH = 1e-6;     // m: spacing and footprint floor before dividing or log2
const float MIN_JACOBIAN = 1e-3;   // floor of the foam ramp's width and of the FFT's 1 + λD_x,x
const float MIN_OCTAVES = 1e-3;    // floor of a cascade's width in octaves
const int HEIGHT_CORRECTIONS = 3;  // fixed-point steps of OceanWaterHeight (as gasgiant)
const float NEAR_SPACING = 0.05;   // m: sample spacing for the height at the near plane
const float KEEP_FROM = 2.0;       // footprints per wavelength: a wave this short is dropped
const float KEEP_TO = 6.0;         // and one this long is kept whole
const float MEAN_COS2 = 0.5;       // mean of cos² over a period: slope variance = ½ (kA)²

// Weight [0, 1] of the displacement at horizontal distance |off| (m) from the camera: 1 up to
// uFadeStart, 0 from uFadeEnd on, so the displaced mesh meets the flat far plane.
float OceanFade(vec2 off) {
    return 1.0 - smoothstep(uFadeStart, uFadeEnd, length(off));
}

// Texture coordinate of cascade i at the rest point camera.xz + off (m); wraps by repeat.
vec2 CascadeUV(int i, vec2 off) {
    return uCascadeUV[i].xy + off * uCascadeUV[i].z;
}

// Mip level that keeps a cascade from aliasing when sampled every `spacing` metres (N/L texels
// per metre). A zero spacing is floored at MIN_LENGTH, so log2 never sees 0.
float CascadeLod(int i, float spacing) {
    return max(0.0, log2(max(spacing * uCascadeUV[i].w, MIN_LENGTH)));
}

// The FFT's displacement (λD_x, η, λD_z) in metres, summed over the active cascades.
vec3 FFTDisplacement(vec2 off, float spacing) {
    vec3 d = textureLod(uDisp0, CascadeUV(0, off), CascadeLod(0, spacing)).xyz;
    if (OCEAN_HAS_CASCADE(1)) {
        d += textureLod(uDisp1, CascadeUV(1, off), CascadeLod(1, spacing)).xyz;
    }
    if (OCEAN_HAS_CASCADE(2)) {
        d += textureLod(uDisp2, CascadeUV(2, off), CascadeLod(2, spacing)).xyz;
    }
    if (OCEAN_HAS_CASCADE(3)) {
        d += textureLod(uDisp3, CascadeUV(3, off), CascadeLod(3, spacing)).xyz;
    }
    return d;
}

// Displacement (D_x, η, D_z) in metres of the rest point camera.xz + off, faded at distance.
// Sine: η = A·sin(k·D·x + ωt + φ), no horizontal motion. Gerstner: P = x + Σ(D·A·cos f, A·sin f)
// with f = k·D·x − ωt + φ (spec/000 eq. 2.5). FFT: the cascades' sum. spacing (m): the
// distance between samples, for the FFT's mip level.
vec3 OceanDisplacement(vec2 off, float spacing) {
    vec3 d = vec3(0.0);
    if (OCEAN_MODEL_IS(0)) {
        float f = uSine.z * dot(uSine.xy, off) + uSinePhase.x * uTime + uSinePhase.y;
        d = vec3(0.0, uSine.w * sin(f), 0.0);
    } else if (OCEAN_MODEL_IS(1)) {
        // the Gerstner position, summed over the waves
        for (int i = 0; i < uGerstnerCount; ++i) {
            vec4 a = uGerstnerA[i];
            float f = a.z * dot(a.xy, off) - uGerstnerB[i].x * uTime + uGerstnerB[i].y;
            float c = cos(f);
            d += vec3(a.x * a.w * c, a.w * sin(f), a.y * a.w * c);
        }
    } else {
        d = FFTDisplacement(off, spacing);
    }
    return d * OceanFade(off);
}

// Height (m) of the water above the world point camera.xz + off. The displacement moves rest
// points sideways, so x₀ + D_xz(x₀) = x_q is inverted by the fixed point x₀ ← x_q − D_xz(x₀)
// (spec/000 §1.3, fig. 3.2): 3 corrections and a final read, as gasgiant's GetWaterHeight.
// Failure case: very choppy water (|∂D/∂x| near 1) converges slowly; the count stays fixed.
float OceanWaterHeight(vec2 off, float spacing) {
    vec3 d = OceanDisplacement(off, spacing);
    for (int i = 0; i < HEIGHT_CORRECTIONS; ++i) d = OceanDisplacement(off - d.xz, spacing);
    return d.y;
}

// Whether a pixel looks out from under the water: its ray starts on the near plane
// (ndc.xy, z = −1), below the water height there. A camera exactly at the surface shows the
// waterline this way. cameraY: the camera's height (m) above the mean sea level.
uniform mat4 uInvViewProjRel;    // inverse view-projection of camera-relative positions
bool OceanPixelStartsUnderwater(vec2 ndc, float cameraY) {
    vec4 q = uInvViewProjRel * vec4(ndc, -1.0, 1.0);
    vec3 nearRel = q.xyz / q.w;
    return cameraY + nearRel.y < OceanWaterHeight(nearRel.xz, NEAR_SPACING);
}

uniform vec4 uCascadeBand[4];  // (k_lo, k_hi, mss of the cascade, 0)

// The FFT's slope and foam textures are mip-filtered for the pixel by the derivatives of the
// rest point across the screen: implicit in a pass that rasterises the surface, given
// explicitly (oceanOffDx, oceanOffDy: d off / dx, d off / dy, set before OceanSurface) in a pass
// that shades from stored inputs (OCEAN_EXPLICIT_GRADIENTS; glsl/ocean/shade.frag), where
// neighbouring pixels may belong to different triangles.
// (A function, not a macro: a macro this long needs a line continuation, which GLSL has only
// from 4.20 on.)
#ifdef OCEAN_EXPLICIT_GRADIENTS
vec2 oceanOffDx = vec2(0.0);
vec2 oceanOffDy = vec2(0.0);
#endif

vec4 OceanTex(sampler2D s, int cascade, vec2 uv) {
#ifdef OCEAN_EXPLICIT_GRADIENTS
    float scale = uCascadeUV[cascade].z;
    return textureGrad(s, uv, oceanOffDx * scale, oceanOffDy * scale);
#else
    return texture(s, uv);
#endif
}

// Share [0, 1] of a wave's slope a pixel can draw: 0 for a wavelength (m) under two footprints
// (m), 1 over six, smooth between. A zero footprint is floored at MIN_LENGTH.
float WaveKeep(float wavelength, float footprint) {
    return smoothstep(KEEP_FROM, KEEP_TO, wavelength / max(footprint, MIN_LENGTH));
}

// Unit normal, foam [0, 1] and lost slope variance at the rest point camera.xz + off, filtered
// for a pixel footprint (m): waves shorter than about two footprints cannot be drawn, so their
// slopes leave the normal and their variance goes to lostMss (it widens the glitter instead of
// aliasing). The analytic models filter per wave (WaveKeep); the FFT by mip-mapping, estimating
// the loss per cascade from its slope variance spread evenly over its octaves (a k⁻³ tail).
// Sine: the 1D normal of spec/000 eq. 2.2 turned to the wave direction D,
// (−kA·cos f·D_x, 1, −kA·cos f·D_z)/‖·‖.
// Gerstner: tangent spec/000 eq. 2.7 and binormal spec/000 eq. 2.8 summed over the waves; the
// normal is B × T (spec/000 eq. 2.4 prints T × B, which points down in a right-handed y-up
// frame); foam where the horizontal Jacobian det ∂(X,Z)/∂(x,z) falls below uFoamThreshold
// (a loop when < 0), over a ramp uFoamWidth wide.
// FFT: up to four cascades of displacement (λD_x, η, λD_z, J), derivatives
// (η_x, η_z, λD_x,x, λD_z,z) and foam, summed; the thesis's slope
// s = (η_x/(1+λD_x,x), η_z/(1+λD_z,z)).
// Failure case: where the FFT surface folds (J ≤ 0) the denominators are clamped at 1e-3, so a
// fold gives a steep but finite, upward normal.
void OceanSurface(vec2 off, float footprint, out vec3 n, out float foam, out float lostMss) {
    foam = 0.0;
    lostMss = 0.0;
    if (OCEAN_MODEL_IS(0)) {
        float f = uSine.z * dot(uSine.xy, off) + uSinePhase.x * uTime + uSinePhase.y;
        float keep = WaveKeep(TWO_PI / uSine.z, footprint);
        float s0 = uSine.z * uSine.w;
        float s = s0 * cos(f) * keep;
        n = normalize(vec3(-s * uSine.x, 1.0, -s * uSine.y));
        lostMss = MEAN_COS2 * s0 * s0 * (1.0 - keep * keep);
    } else if (OCEAN_MODEL_IS(1)) {
        vec3 t = vec3(1.0, 0.0, 0.0);
        vec3 b = vec3(0.0, 0.0, 1.0);
        for (int i = 0; i < uGerstnerCount; ++i) {
            vec4 a = uGerstnerA[i];
            float f = a.z * dot(a.xy, off) - uGerstnerB[i].x * uTime + uGerstnerB[i].y;
            float keep = WaveKeep(TWO_PI / a.z, footprint);
            float s = uGerstnerB[i].z * keep;
            float sf = sin(f), cf = cos(f);
            t += vec3(-a.x * a.x * s * sf, a.x * s * cf, -a.x * a.y * s * sf);
            b += vec3(-a.x * a.y * s * sf, a.y * s * cf, -a.y * a.y * s * sf);
            lostMss += MEAN_COS2 * uGerstnerB[i].z * uGerstnerB[i].z * (1.0 - keep * keep);
        }
        n = normalize(cross(b, t));  // B × T: upward
        float jac = t.x * b.z - t.z * b.x;
        foam = clamp((uFoamThreshold - jac) / max(uFoamWidth, MIN_JACOBIAN), 0.0, 1.0);
    } else {
        vec2 uv0 = CascadeUV(0, off);
        vec4 g = OceanTex(uDeriv0, 0, uv0);
        foam = uFoamWeight[0] * OceanTex(uFoam0, 0, uv0).r;
        if (OCEAN_HAS_CASCADE(1)) {
            vec2 uv = CascadeUV(1, off);
            g += OceanTex(uDeriv1, 1, uv);
            foam += uFoamWeight[1] * OceanTex(uFoam1, 1, uv).r;
        }
        if (OCEAN_HAS_CASCADE(2)) {
            vec2 uv = CascadeUV(2, off);
            g += OceanTex(uDeriv2, 2, uv);
            foam += uFoamWeight[2] * OceanTex(uFoam2, 2, uv).r;
        }
        if (OCEAN_HAS_CASCADE(3)) {
            vec2 uv = CascadeUV(3, off);
            g += OceanTex(uDeriv3, 3, uv);
            foam += uFoamWeight[3] * OceanTex(uFoam3, 3, uv).r;
        }
        vec2 s = g.xy / max(vec2(1.0) + g.zw, vec2(MIN_JACOBIAN));
        n = normalize(vec3(-s.x, 1.0, -s.y));
        foam = clamp(foam, 0.0, 1.0);
        float kfp = PI / max(footprint, MIN_LENGTH);  // the shortest wave the pixel can show
        for (int i = 0; i < OCEAN_CASCADE_COUNT; ++i) {
            vec4 band = uCascadeBand[i];
            float octaves = max(log2(band.y / band.x), MIN_OCTAVES);
            float lost = clamp(log2(band.y / kfp) / octaves, 0.0, 1.0);
            lostMss += band.z * lost;
        }
    }
}
