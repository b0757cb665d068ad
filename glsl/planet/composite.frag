#version 330 core
// The planet scene's scattering pass (spec/002 §2.3–§2.5; Hillaire 2020 beyond the thesis): for
// each pixel, the surface it sees (a mesh from the G-buffer, the analytic Earth, or space with
// stars) and the light the atmosphere removes and adds on the way to the camera. Output is linear
// radiance Color_out + Color_in; the thesis's exposure (§1.6) is the output's tone map.
//   METHOD 1  first approximation: nested midpoint sums over the unclipped camera→object
//             segment, to the universe sphere for the sky (§2.3; "Method 1's universe sphere")
//   METHOD 2  second: the optical-depth LUT for the sun, the segment clipped to the air (§2.4)
//   METHOD 3  final: method 2 + shadow-map visibility V(P) in the integral (§2.5)
//   METHOD 4  Hillaire 2020's LUT lookups with the same constants
// Failure cases guarded: rays that miss or graze the air (methods 2–4: no scattering, T = 1),
// float32 at planet scale (camera-relative positions), seams of the reduced march (see below).
#include "atmosphere/model.glsl"
#include "camera.glsl"

#if METHOD >= 2 && METHOD <= 3
#define SUN_DEPTH_LUT
#endif
#if METHOD == 3
#define SHADOWED_INSCATTER
#endif

uniform vec3 uCameraLocal;   // camera in the local frame at the scene origin (m)

#include "atmosphere/optical_depth_lut.glsl"
#include "atmosphere/sun_transmittance.glsl"
// Shadow comparisons are the hardware's unless SHADOW_COMPARE_MANUAL (shadow.glsl).
#include "shadow.glsl"
// With SURFACES_IN_GBUFFER (the default, planet.ground_pass = gbuffer) the analytic ground and
// the background are not shaded here: the surfaces' pass shades them once into the G-buffer's
// colour where no mesh is (planet/ground.frag), so this pass reads Color_original(O) of every
// pixel with one texelFetch and its time is what the method's integral costs. Without it
// (planet.ground_pass = scattering) they are shaded here (planet/surroundings.glsl), the same
// image. Either way the ground's 5-octave noise is, with GROUND_NOISE_BAKED, two lookups (a fine
// gnomonic cap about the scene's origin and a coarse seamless cubemap, baked once by
// planet/ground_noise_bake.frag and rebuilt only when planet.ground_noise_size changes) instead
// of 5 octaves of Perlin noise that every method paid alike and that compressed the methods'
// ratios; the live sum (planet.ground_noise = live) is the reference. The bake moves coastlines
// by a fraction of a texel; the bench's "changes" section states mean and max |Δ|.
#ifndef SURFACES_IN_GBUFFER
#include "surroundings.glsl"
#endif
#include "atmosphere/inscatter.glsl"
// Reduced-resolution march (methods 1–3, beyond the thesis: the field's way with light shafts;
// planet.march_scale): MARCH_PASS 1 marches one pixel of every B × B block (AmortisedPixel of
// common/amortise.glsl) into a grid, with the distance beside the in-scattering; 2 (every pixel)
// interpolates the grid where it can (MarchUpsample), writing window depth 0 there and 1
// elsewhere; 3 is this pass's full march drawn on the far plane with the depth test '<=', so it
// shades only the pixels 2 could not fill (a march compiled into 2 would cost every pixel its
// loops on a software rasteriser). Without MARCH_PASS (planet.march_scale = full) every pixel
// marches: the thesis's method, the reference.
#ifndef MARCH_PASS
#define MARCH_PASS 0
#endif
#if MARCH_PASS != 0
#include "amortise.glsl"
#endif
#if METHOD == 4
#ifndef HILLAIRE_PART
#define HILLAIRE_PART 0
#endif
#include "atmosphere/hillaire/hillaire_lookup.glsl"
#endif

in vec2 vUV;

uniform sampler2D uGColor;
uniform sampler2D uGPosition;
uniform float uUniverseRadius;    // method 1 integrates to this sphere for rays into space
uniform vec3 uUniverseCenter;     // its centre relative to the camera: the Earth's, or 0
uniform int uDebugView;           // the thesis's figures: 0 final, 1 in-scattering on black,
                                  // 2 out-scattering on white

const float SPACE_DISTANCE = 1.0e30;   // m: GroundDistance's value for a ray into space
const float SPACE_THRESHOLD = 1.0e29;  // m: a distance this far or farther is space
const float MESH_FLAG = 0.5;           // G-buffer position .w above this: a mesh covers the pixel

// Method 1's universe sphere (§2.3, §2.4 item 2). The thesis's first approximation integrates
// from the camera to the visible point, which for the sky is "the sphere that contains the rest
// of the scene and represents the universe", so part of its samples lie outside the atmosphere.
// The thesis gives no radius; its figure (§2.3: sun at zenith, N_STEPS = 30) bounds it. The sky
// there is blue, so the zenith ray's 30 steps must reach into the air (a sphere 10 000 km away
// puts the first sample at 167 km: a black sky above ~15°), and the sphere contains the Earth and
// the atmosphere, so it hugs them: centred on the Earth, radius beyond R + 60 km. Our default,
// uUniverseRadius = R + 200 km about the Earth's centre, lies in that range and contains a space
// camera at 3 × the atmosphere's height (§9 criterion 19), as the thesis's space views are taken
// inside it. The zenith ray is then 200 km long (first sample at 3.3 km) and a horizontal one
// ~1600 km (53 km steps); with the thesis's τ(PC) rule (the whole step added before use:
// uThesisPcRule, on for method 1 by default) such a step extinguishes its own sample, so the rows
// just above the horizon turn dark and the bright orange line moves up to ~4°: the thesis's
// "orange horizon line displaced upward ... a black band" (§2.3). With the midpoint rule the band
// all but vanishes (≥ 95 % of method 3 there), so the rule is part of the figure. The black-sky
// case stays reachable: planet.universe_centre = camera, planet.universe_radius = 1e7.
// Returns the distance (m) where dir leaves the sphere; a ray that misses it gets 0 (so no
// in-scattering: the sphere contains the atmosphere, which such a ray cannot cross).
float UniverseDistance(vec3 dir) {
    vec2 t;
    return RaySphereIntersect(vec3(0.0), dir, uUniverseCenter, uUniverseRadius, t) ? max(t.y, 0.0)
                                                                                    : 0.0;
}

#if METHOD == 4
out vec4 fragColor;

// Method 4's pass is lookups only (Hillaire 2020 §5.3–5.4), linear radiance out. HILLAIRE_PART
// says which pixels a program shades: 1 those no mesh covers (drawn on the far plane with the
// depth test '<=' against the G-buffer's depth: the sky, or the analytic ground — the sky-view
// LUT's rays end exactly there), 2 the meshes (the test '>'), 0 both, chosen per pixel (one pass
// where the depth cannot be shared). Each program then carries one path's code only, which is
// what a software rasteriser, running every branch, pays for.
void main() {
    ivec2 px = ivec2(gl_FragCoord.xy);
    vec3 dir = CameraRayDirection(vUV);
    vec3 inscatter, transmittance, surface;
#if HILLAIRE_PART == 2
    bool mesh = true;
#elif HILLAIRE_PART == 1
    bool mesh = false;
#else
    bool mesh = texelFetch(uGPosition, px, 0).w > MESH_FLAG;
#endif
#if HILLAIRE_PART != 1
    if (mesh) {
        vec3 gpos = texelFetch(uGPosition, px, 0).xyz;
        float dist = length(gpos);
        HillaireAerial(vUV, gpos / dist, dist, inscatter, transmittance);
        surface = texelFetch(uGColor, px, 0).rgb;
    }
#endif
#if HILLAIRE_PART != 2
    if (!mesh) {
        HillaireSkyView(dir, inscatter, transmittance);
#ifdef SURFACES_IN_GBUFFER
        surface = texelFetch(uGColor, px, 0).rgb;   // planet/ground.frag's
#else
        float dist = GroundDistance(dir);
        surface = dist >= SPACE_THRESHOLD ? Background(dir) : GroundColor(dir * dist);
#endif
    }
#endif
    if (uDebugView == 1) surface = vec3(0.0);
    if (uDebugView == 2) {
        surface = vec3(1.0);
        inscatter = vec3(0.0);
    }
    fragColor = vec4(surface * transmittance + inscatter, 1.0);
}
#else
// What pixel px (uv its centre) sees: its unit ray, the distance (m) to the surface (a mesh's,
// the analytic ground's, or SPACE_DISTANCE into space) and Color_original of that surface
// (linear). G-buffer positions are camera-relative, so float32 holds them at planet scale; the
// analytic ground takes no shadow-map bias (it cannot shadow itself: GroundColor).
void PixelView(ivec2 px, vec2 uv, out vec3 dir, out float dist, out bool space,
               out vec3 surface) {
    vec4 gpos = texelFetch(uGPosition, px, 0);
    dir = CameraRayDirection(uv);
#ifdef SURFACES_IN_GBUFFER
    surface = texelFetch(uGColor, px, 0).rgb;   // a mesh's, or planet/ground.frag's
#endif
    space = false;
    if (gpos.w > MESH_FLAG) {
        dist = length(gpos.xyz);
        dir = gpos.xyz / dist;
#ifndef SURFACES_IN_GBUFFER
        surface = texelFetch(uGColor, px, 0).rgb;
#endif
    } else {
        dist = GroundDistance(dir);
        space = dist >= SPACE_THRESHOLD;
#ifndef SURFACES_IN_GBUFFER
        surface = space ? Background(dir) : GroundColor(dir * dist);
#endif
    }
}

// The method's integral in front of that surface (dist in m) with `steps` view-ray samples (0:
// none): linear in-scattered radiance and per-channel transmittance. Out- and in-scattering are
// spec/002 §1.4 and §1.5 (the thesis numbers no equation), discretised as in §1.7
// (atmosphere/inscatter.glsl), the sun's optical depth from §1.8's LUT (methods 2–3). Method 1
// runs the unclipped segment to the universe sphere; methods 2–4 clip it to the atmosphere, and
// a ray that misses it, or whose segment lies behind the camera, gets none and T = 1.
void Atmosphere(vec3 dir, float dist, bool space, int steps, out vec3 inscatter,
                out vec3 transmittance) {
    float t0, t1;
#if METHOD == 1
    t0 = 0.0;
    t1 = space ? UniverseDistance(dir) : dist;
#else
    vec2 seg = AtmosphereSegment(dir, space ? SPACE_DISTANCE : dist);
    t0 = seg.x;
    t1 = seg.y;
#endif
    vec3 depthPC = vec3(0.0);
    bool crosses = t1 > t0 && t0 >= 0.0;
    inscatter = crosses ? InScatterN(dir, t0, t1, steps, depthPC) : vec3(0.0);
    transmittance = crosses ? TransmittanceFromDepths(depthPC) : vec3(1.0);
}

#if MARCH_PASS == 1
// The reduced-resolution march: grid texel t marches full-resolution pixel t·B + sub exactly as
// the full-resolution pass would (its ray and its G-buffer distance), and stores the distance it
// marched to (SPACE_DISTANCE into space) beside the in-scattering for the upsampling's depth test.
layout(location = 0) out vec4 outInscatter;
layout(location = 1) out vec4 outTransmittance;
void main() {
    ivec2 px = min(AmortisedPixel(), ivec2(uAmortiseFullSize) - 1);
    vec3 dir, surface, inscatter, transmittance;
    float dist;
    bool space;
    PixelView(px, AmortisedUV(px), dir, dist, space, surface);
    Atmosphere(dir, dist, space, uSteps, inscatter, transmittance);
    outInscatter = vec4(inscatter, space ? SPACE_DISTANCE : dist);
    outTransmittance = vec4(transmittance, 0.0);
}
#else
out vec4 fragColor;
#if MARCH_PASS == 2
uniform sampler2D uMarchInscatter;      // the grid's in-scattering, a = the distance marched (m)
uniform sampler2D uMarchTransmittance;  // the grid's transmittance
uniform float uMarchContrast;           // largest relative spread of 4 grid values interpolated
#ifndef MARCH_DEPTH_TOLERANCE
#define MARCH_DEPTH_TOLERANCE 0.02
#endif
const float FLOAT_HUGE = 1.0e38;            // above any radiance: the running minimum's start
const float MIN_INVERSE_DISTANCE = 1.0e-30; // 1/m: Σ w/d of four sky points (0) floored

// Depth-aware upsampling of the grid at px (its distance `key` in m, SPACE_DISTANCE into space):
// the bilinear interpolation of the 4 grid points around px. It stands (true) when the
// interpolated inverse distance of those points agrees with px's own within
// MARCH_DEPTH_TOLERANCE (AmortiseDepthAgree: 1/d is affine across the screen on a plane, so one
// surface passes and a silhouette — a mesh's edge, the horizon, the limb — does not), every
// point lies inside the grid, and the 4 points' values are close: each channel of the
// in-scattering within uMarchContrast of the largest, of the transmittance within
// uMarchContrast, over the whole cell (a shaft's edge, the limb's thin glow seen from space
// change faster than interpolation follows); else px marches its own ray (MARCH_PASS 3). So does
// every pixel beside a mesh's edge (one of its 4 neighbours is a mesh and it is not, or the
// reverse): a ray that grazes a ridge can run in its shadow for kilometres, a dark line one
// pixel wide that no grid ray meets. Failure cases: grid points past the image's last row or
// column are not interpolated from (their pixels march); the sky's distance interpolates as
// 1/d = 0, its sum floored. The choice depends on neither the surface nor the debug view (the
// three views make one image) and is the same for radiance scaled by a power of two (the sun's
// intensity).
bool MarchUpsample(ivec2 px, float key, out vec3 inscatter, out vec3 transmittance) {
    ivec2 last = textureSize(uMarchInscatter, 0) - 1;
    ivec2 g0 = px >> uAmortiseShift;
    vec2 f = vec2(px - (g0 << uAmortiseShift)) / float(uAmortiseBlock);
    inscatter = vec3(0.0);
    transmittance = vec3(0.0);
    vec3 loL = vec3(FLOAT_HUGE), hiL = vec3(0.0), loT = vec3(1.0), hiT = vec3(0.0);
    bool agree = true;
    float inverse = 0.0;   // Σ w / d
    for (int dy = 0; dy <= 1; ++dy) {
        for (int dx = 0; dx <= 1; ++dx) {
            float w = (dx == 1 ? f.x : 1.0 - f.x) * (dy == 1 ? f.y : 1.0 - f.y);
            ivec2 t = g0 + ivec2(dx, dy);
            bool inside = all(lessThanEqual(t, last));   // past the last row or column: march
            t = min(t, last);
            vec4 v = texelFetch(uMarchInscatter, t, 0);
            vec3 T = texelFetch(uMarchTransmittance, t, 0).rgb;
            if (w > 0.0) agree = agree && inside;
            inverse += w / v.a;
            // the spread over all 4, weighted or not: a pixel on a grid row or column also
            // sees the change across its cell (a shadow's edge the grid ray beside it missed)
            loL = min(loL, v.rgb);
            hiL = max(hiL, v.rgb);
            loT = min(loT, T);
            hiT = max(hiT, T);
            inscatter += w * v.rgb;
            transmittance += w * T;
        }
    }
    float mesh = texelFetch(uGPosition, px, 0).w;
    ivec2 top = ivec2(uAmortiseFullSize) - 1;
    for (int k = 0; k < 4; ++k) {
        ivec2 q = px + ivec2(k == 0 ? -1 : k == 1 ? 1 : 0, k == 2 ? -1 : k == 3 ? 1 : 0);
        agree = agree && texelFetch(uGPosition, clamp(q, ivec2(0), top), 0).w == mesh;
    }
    float d = 1.0 / max(inverse, MIN_INVERSE_DISTANCE);
    return agree && abs(key - d) <= MARCH_DEPTH_TOLERANCE * max(key, d)
        && all(lessThanEqual(hiL - loL, uMarchContrast * hiL))   // scale-free: 0 ≤ 0 passes
        && all(lessThanEqual(hiT - loT, vec3(uMarchContrast)));
}
#endif

// Methods 1–3, one pixel: its surface times the transmittance plus the in-scattering (linear
// radiance), the debug views replacing surface or in-scattering as the thesis's figures do.
void main() {
    ivec2 px = ivec2(gl_FragCoord.xy);
    vec3 dir, surface, inscatter, transmittance;
    float dist;
    bool space;
    PixelView(px, vUV, dir, dist, space, surface);
    if (uDebugView == 1) surface = vec3(0.0);
    if (uDebugView == 2) surface = vec3(1.0);
#if MARCH_PASS == 2
    // interpolated, or marked for MARCH_PASS 3 (window depth 1: its far-plane draw passes '<='
    // there only; 0 where the interpolation stands)
    bool filled = MarchUpsample(px, space ? SPACE_DISTANCE : dist, inscatter, transmittance);
    gl_FragDepth = filled ? 0.0 : 1.0;
#else
    Atmosphere(dir, dist, space, uSteps, inscatter, transmittance);
#endif
    if (uDebugView == 2) inscatter = vec3(0.0);
    fragColor = vec4(surface * transmittance + inscatter, 1.0);
}
#endif
#endif
