// The three wave models of the maritime thesis, chapter 2 (spec/000 §1.1), behind one interface:
//   OceanDisplacement(off, spacing) → (D_x, η, D_z) [m] at the rest point camera.xz + off;
//   OceanSurface(off, n, foam, mss) → unit normal, foam in [0, 1] and the resolved slope variance.
// Rest points are given relative to the camera (off), and every phase that depends on the absolute
// position is folded on the CPU in float64 (uSinePhase, uGerstnerB.y, uCascadeUV.xy), so float32
// holds at any distance from the origin.
//   0 = sine (spec/000 §1.1(a)): η = A·sin(k·D·x + ωt + φ), no horizontal motion, analytic
//       normal (−kA·cos·D_x, 1, −kA·cos·D_z)/‖·‖ — the 1D normal of spec/000 eq. 2.2 turned to
//       the wind.
//   1 = Gerstner (spec/000 eq. 2.5, spec/000 eq. 2.7, spec/000 eq. 2.8): P = x + Σ(D·A·cos f,
//       A·sin f), f = k·D·x − ωt + φ; the normal is B × T (spec/000 eq. 2.4 prints T × B, which
//       points down in a right-handed y-up frame);
//       foam where the horizontal Jacobian det ∂(X,Z)/∂(x,z) falls below the threshold (loops: < 0).
//   2 = FFT (Tessendorf; §1.1(d)–(e)): up to four cascades of displacement (λD_x, η, λD_z, J),
//       derivative (η_x, η_z, λD_x,x, λD_z,z) and foam textures, summed; normal by the thesis's
//       slope formula s = (η_x/(1+λD_x,x), η_z/(1+λD_z,z)); the denominators are clamped at 1e-3
//       where the surface folds (J ≤ 0), so a fold gives a steep but finite, upward normal.
// Guards: k = 0 is never sent (CPU), Σ over at most 64 waves, a fade to flat water at distance
// (uFadeStart, uFadeEnd) so the mesh meets the analytic far plane; normals are never faded, only
// filtered by the pixel footprint (OceanSurface).

#include "math.glsl"

uniform int uWaveModel;          // 0 sine, 1 Gerstner, 2 FFT
uniform float uTime;             // seconds
uniform float uFadeStart;        // m: displacement starts fading to flat water here
uniform float uFadeEnd;          // m: and is flat from here on
uniform float uFoamThreshold;    // Jacobian below which the surface foams (Gerstner; the FFT bakes it)
uniform float uFoamWidth;        // Jacobian range of the foam ramp

uniform vec4 uSine;              // (D_x, D_z, k, A)
uniform vec2 uSinePhase;         // (ω, φ + k·D·camera.xz mod 2π)

#define MAX_GERSTNER 64
uniform int uGerstnerCount;
uniform vec4 uGerstnerA[MAX_GERSTNER];  // (D_x, D_z, k, A)
uniform vec4 uGerstnerB[MAX_GERSTNER];  // (ω, φ + k·D·camera.xz mod 2π, s = kA, 0)

uniform int uCascades;
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

float OceanFade(vec2 off) {
    return 1.0 - smoothstep(uFadeStart, uFadeEnd, length(off));
}

vec2 CascadeUV(int i, vec2 off) {
    return uCascadeUV[i].xy + off * uCascadeUV[i].z;
}

// Mip level that keeps a cascade from aliasing when sampled every `spacing` metres.
float CascadeLod(int i, float spacing) {
    return max(0.0, log2(max(spacing * uCascadeUV[i].w, 1e-6)));
}

vec3 FFTDisplacement(vec2 off, float spacing) {
    vec3 d = textureLod(uDisp0, CascadeUV(0, off), CascadeLod(0, spacing)).xyz;
    if (uCascades > 1) d += textureLod(uDisp1, CascadeUV(1, off), CascadeLod(1, spacing)).xyz;
    if (uCascades > 2) d += textureLod(uDisp2, CascadeUV(2, off), CascadeLod(2, spacing)).xyz;
    if (uCascades > 3) d += textureLod(uDisp3, CascadeUV(3, off), CascadeLod(3, spacing)).xyz;
    return d;
}

vec3 OceanDisplacement(vec2 off, float spacing) {
    vec3 d = vec3(0.0);
    if (uWaveModel == 0) {
        float f = uSine.z * dot(uSine.xy, off) + uSinePhase.x * uTime + uSinePhase.y;
        d = vec3(0.0, uSine.w * sin(f), 0.0);
    } else if (uWaveModel == 1) {
        // spec/000 eq. 2.5: the Gerstner position, summed over the waves
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

// Height of the water above the world point camera.xz + off: the displacement moves rest points
// sideways, so invert x₀ + D_xz(x₀) = x_q by x₀ ← x_q − D_xz(x₀) (spec/000 §1.3, fig. 3.2;
// 3 corrections and a final read, as gasgiant's GetWaterHeight).
float OceanWaterHeight(vec2 off, float spacing) {
    vec3 d = OceanDisplacement(off, spacing);
    for (int i = 0; i < 3; ++i) d = OceanDisplacement(off - d.xz, spacing);
    return d.y;
}

// Whether a pixel looks out from under the water: its ray starts on the near plane (ndc.xy, z = −1),
// below the water height there. A camera exactly at the surface shows the waterline this way.
uniform mat4 uInvViewProjRel;    // inverse view-projection of camera-relative positions
bool OceanPixelStartsUnderwater(vec2 ndc, float cameraY) {
    vec4 q = uInvViewProjRel * vec4(ndc, -1.0, 1.0);
    vec3 nearRel = q.xyz / q.w;
    return cameraY + nearRel.y < OceanWaterHeight(nearRel.xz, 0.05);
}

// Normal and foam at the rest point camera.xz + off, filtered for a pixel footprint [m]: waves
// shorter than about two footprints cannot be drawn, so their slopes are removed from the normal
// and their slope variance is returned in lostMss (it widens the glitter instead of aliasing).
// Analytic models filter per wave; the FFT filters by mip-mapping and estimates the loss per
// cascade from its slope variance spread evenly over its octaves (a k⁻³ tail does that).
uniform vec4 uCascadeBand[4];  // (k_lo, k_hi, mss of the cascade, 0)

// The FFT's slope and foam textures are mip-filtered for the pixel by the derivatives of the rest
// point across the screen: implicit in a pass that rasterises the surface, given explicitly
// (oceanOffDx, oceanOffDy: d off / dx, d off / dy, set before OceanSurface) in a pass that shades
// from stored inputs (OCEAN_EXPLICIT_GRADIENTS; glsl/ocean/shade.frag), where neighbouring pixels
// may belong to different triangles.
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

float WaveKeep(float wavelength, float footprint) {
    return smoothstep(2.0, 6.0, wavelength / max(footprint, 1e-6));
}

void OceanSurface(vec2 off, float footprint, out vec3 n, out float foam, out float lostMss) {
    foam = 0.0;
    lostMss = 0.0;
    if (uWaveModel == 0) {
        float f = uSine.z * dot(uSine.xy, off) + uSinePhase.x * uTime + uSinePhase.y;
        float keep = WaveKeep(TWO_PI / uSine.z, footprint);
        float s0 = uSine.z * uSine.w;
        float s = s0 * cos(f) * keep;
        // spec/000 eq. 2.2, turned to the wave direction D
        n = normalize(vec3(-s * uSine.x, 1.0, -s * uSine.y));
        lostMss = 0.5 * s0 * s0 * (1.0 - keep * keep);
    } else if (uWaveModel == 1) {
        vec3 t = vec3(1.0, 0.0, 0.0);  // spec/000 eq. 2.7
        vec3 b = vec3(0.0, 0.0, 1.0);  // spec/000 eq. 2.8
        for (int i = 0; i < uGerstnerCount; ++i) {
            vec4 a = uGerstnerA[i];
            float f = a.z * dot(a.xy, off) - uGerstnerB[i].x * uTime + uGerstnerB[i].y;
            float keep = WaveKeep(TWO_PI / a.z, footprint);
            float s = uGerstnerB[i].z * keep;
            float sf = sin(f), cf = cos(f);
            t += vec3(-a.x * a.x * s * sf, a.x * s * cf, -a.x * a.y * s * sf);
            b += vec3(-a.x * a.y * s * sf, a.y * s * cf, -a.y * a.y * s * sf);
            lostMss += 0.5 * uGerstnerB[i].z * uGerstnerB[i].z * (1.0 - keep * keep);
        }
        // spec/000 eq. 2.4, as B × T (upward in a right-handed y-up frame)
        n = normalize(cross(b, t));
        float jac = t.x * b.z - t.z * b.x;
        foam = clamp((uFoamThreshold - jac) / max(uFoamWidth, 1e-3), 0.0, 1.0);
    } else {
        vec2 uv0 = CascadeUV(0, off);
        vec4 g = OceanTex(uDeriv0, 0, uv0);
        foam = uFoamWeight[0] * OceanTex(uFoam0, 0, uv0).r;
        if (uCascades > 1) {
            vec2 uv = CascadeUV(1, off);
            g += OceanTex(uDeriv1, 1, uv);
            foam += uFoamWeight[1] * OceanTex(uFoam1, 1, uv).r;
        }
        if (uCascades > 2) {
            vec2 uv = CascadeUV(2, off);
            g += OceanTex(uDeriv2, 2, uv);
            foam += uFoamWeight[2] * OceanTex(uFoam2, 2, uv).r;
        }
        if (uCascades > 3) {
            vec2 uv = CascadeUV(3, off);
            g += OceanTex(uDeriv3, 3, uv);
            foam += uFoamWeight[3] * OceanTex(uFoam3, 3, uv).r;
        }
        vec2 s = g.xy / max(vec2(1.0) + g.zw, vec2(1e-3));
        n = normalize(vec3(-s.x, 1.0, -s.y));
        foam = clamp(foam, 0.0, 1.0);
        float kfp = PI / max(footprint, 1e-6);  // the shortest wave the pixel can show
        for (int i = 0; i < uCascades; ++i) {
            vec4 band = uCascadeBand[i];
            float lost = clamp(log2(band.y / kfp) / max(log2(band.y / band.x), 1e-3), 0.0, 1.0);
            lostMss += band.z * lost;
        }
    }
}
