#version 330 core
// =============================================================================================
// The planet scene's scattering pass: for each pixel, the surface it sees (a mesh from the
// G-buffer, the analytic Earth sphere, or space with stars) and the light the atmosphere
// removes and adds on the way to the camera (spec/002):
//   METHOD 1  first approximation: nested midpoint sums over the whole camera→object segment,
//             unclipped, to the universe sphere for the sky, as the thesis did (its dark
//             horizon band comes from here, see "Method 1's universe sphere") (§2.3)
//   METHOD 2  second: optical-depth LUT for the sun integral, segment clipped to the atmosphere
//             (§2.4)
//   METHOD 3  final: method 2 + shadow-map visibility V(P) in the integral (light shafts) (§2.5)
//   METHOD 4  beyond the thesis: Hillaire 2020 transmittance / multiple-scattering / sky-view /
//             aerial-perspective lookups with the same constants
// Output is linear radiance Color_out + Color_in; the thesis's exposure 1 − e^(−pupil·x) (§1.6)
// is applied by the output tone map with the pupil factor computed per frame on the CPU.
// Debug views (the thesis's figures): 1 = in-scattering on black, 2 = out-scattering on white.
// Equations: the thesis numbers none; out- and in-scattering are spec/002 §1.4 and §1.5,
// discretised as in §1.7 (atmosphere/inscatter.glsl), the sun's optical depth via §1.8's LUT.
// Method 1's universe sphere (§2.3, §2.4 item 2): the thesis's first approximation integrates
// from the camera to the visible point — for the sky, "the sphere that contains the rest of the
// scene and represents the universe" — so part of its samples lie outside the atmosphere. Its
// radius is not given; its figure (§2.3: sun at zenith, N_STEPS = 30) bounds it: the sky is
// blue, so the zenith ray's 30 steps must reach into the air (a sphere 10 000 km away puts the
// first sample at 167 km: a black sky above ~15°), while the sphere contains the Earth and
// the atmosphere — so it hugs them: centred on the Earth, a radius beyond R + 60 km. Default
// uUniverseRadius = R + 200 km about the Earth's centre [inference]: inside that range, and it
// contains a space camera at 3 × the atmosphere's height (§9 criterion 19), as the thesis's
// space views are taken inside it. Then the zenith ray is 200 km long (first sample at 3.3 km)
// and a horizontal one ~1600 km (53 km steps); with the thesis's τ(PC) rule (the whole step
// added before use: uThesisPcRule, on for method 1 by default) such a step extinguishes its own
// sample, so the rows just above the horizon turn dark and the bright orange line moves up to
// ~4° — the thesis's "orange horizon line displaced upward ... a black band" (§2.3). With the
// midpoint rule the band all but vanishes (≥ 95 % of method 3 there), so the rule is part of
// the figure. The worse, black-sky case stays reachable: planet.universe_centre = camera,
// planet.universe_radius = 1e7 (the rays into space 10 000 km long).
// Fixed per-pixel work, out of the per-method integral: the ground's 5-octave noise is two
// lookups (GROUND_NOISE_BAKED: a fine gnomonic cap about the scene's origin and a coarse cubemap,
// planet/ground_noise_bake.frag, baked once and rebuilt only when planet.ground_noise_size
// changes) instead of 5 octaves of Perlin noise per ground pixel, which
// every method paid alike and which compressed the methods' ratios; without the define (planet.
// ground_noise = live) the live sum is the reference. The bake moves coastlines by a fraction of
// a texel (bilinear f between texel centres); the image is otherwise the same (the bench's
// "changes" section states mean and max |Δ|). Shadow comparisons are the hardware's unless
// SHADOW_COMPARE_MANUAL (shadow.glsl). With SURFACES_IN_GBUFFER (the default, planet.ground_pass
// = gbuffer) the analytic ground and the background are not shaded here at all: the surfaces'
// pass shades them once into the G-buffer's colour where no mesh is (planet/ground.frag), so this
// pass reads Color_original(O) of every pixel with one texelFetch and its time is what the
// method's integral costs; without the define (planet.ground_pass = scattering) they are shaded
// here as before (planet/surroundings.glsl), the same image.
// Failure cases: method 1 keeps the thesis's own (the unclipped segment and its dark horizon
// band, see above; a ray into space that misses the universe sphere gets no in-scattering, the
// sphere containing the atmosphere); methods 2–4 guard rays that miss or only
// graze the atmosphere (an empty or behind-the-camera segment: no in-scattering, T = 1); the
// asin of the star lookup is clamped; float32 at planet scale: G-buffer positions are
// camera-relative and the Earth centre relative to the camera comes from the CPU in double
// precision; the analytic ground takes no shadow-map depth bias (it cannot shadow itself, see
// GroundColor); the baked noise's cubemap is seamless (GL_TEXTURE_CUBE_MAP_SEAMLESS), so face
// edges do not show.
// =============================================================================================
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
#include "shadow.glsl"
#ifndef SURFACES_IN_GBUFFER
#include "surroundings.glsl"
#endif
#include "atmosphere/inscatter.glsl"
#if METHOD == 4
#ifndef HILLAIRE_PART
#define HILLAIRE_PART 0
#endif
#include "atmosphere/hillaire/hillaire_lookup.glsl"
#endif

in vec2 vUV;
out vec4 fragColor;

uniform sampler2D uGColor;
uniform sampler2D uGPosition;
uniform float uUniverseRadius;    // method 1 integrates to this sphere for rays into space
uniform vec3 uUniverseCenter;     // its centre relative to the camera: the Earth's, or 0
uniform int uDebugView;           // 0 final, 1 in-scattering on black, 2 out-scattering on white

// Method 1's end of a ray into space: where it leaves the universe sphere (0 if it misses it).
float UniverseDistance(vec3 dir) {
    vec2 t;
    return RaySphereIntersect(vec3(0.0), dir, uUniverseCenter, uUniverseRadius, t) ? max(t.y, 0.0)
                                                                                    : 0.0;
}

#if METHOD == 4
// Method 4's pass is lookups only (Hillaire 2020 §5.3–5.4). HILLAIRE_PART says which pixels a
// program shades: 1 those no mesh covers (drawn on the far plane with the depth test '<='
// against the G-buffer's depth: the sky, or the analytic ground — the sky-view LUT's rays end
// exactly there), 2 the meshes (the test '>'), 0 both, chosen per pixel (one pass where the
// depth cannot be shared). Each program then carries one path's code only, which is what a
// software rasteriser, running every branch, pays for.
void main() {
    ivec2 px = ivec2(gl_FragCoord.xy);
    vec3 dir = CameraRayDirection(vUV);
    vec3 inscatter, transmittance, surface;
#if HILLAIRE_PART == 2
    bool mesh = true;
#elif HILLAIRE_PART == 1
    bool mesh = false;
#else
    bool mesh = texelFetch(uGPosition, px, 0).w > 0.5;
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
        surface = dist >= 1.0e29 ? Background(dir) : GroundColor(dir * dist);
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
void main() {
    ivec2 px = ivec2(gl_FragCoord.xy);
    vec4 gpos = texelFetch(uGPosition, px, 0);
    vec3 dir = CameraRayDirection(vUV);
#ifdef SURFACES_IN_GBUFFER
    vec3 surface = texelFetch(uGColor, px, 0).rgb;   // a mesh's, or planet/ground.frag's
#else
    vec3 surface;
#endif
    float dist;
    bool space = false;
    if (gpos.w > 0.5) {
        dist = length(gpos.xyz);
        dir = gpos.xyz / dist;
#ifndef SURFACES_IN_GBUFFER
        surface = texelFetch(uGColor, px, 0).rgb;
#endif
    } else {
        dist = GroundDistance(dir);
        space = dist >= 1.0e29;
#ifndef SURFACES_IN_GBUFFER
        surface = space ? Background(dir) : GroundColor(dir * dist);
#endif
    }
    if (uDebugView == 1) surface = vec3(0.0);
    if (uDebugView == 2) surface = vec3(1.0);

    vec3 inscatter;
    vec3 transmittance;
    float t0, t1;
#if METHOD == 1
    t0 = 0.0;
    t1 = space ? UniverseDistance(dir) : dist;
#else
    vec2 seg = AtmosphereSegment(dir, space ? 1.0e30 : dist);
    t0 = seg.x;
    t1 = seg.y;
#endif
    vec2 depthPC = vec2(0.0);
    bool crosses = t1 > t0 && t0 >= 0.0;
    inscatter = crosses ? InScatter(dir, t0, t1, depthPC) : vec3(0.0);
    transmittance = crosses ? TransmittanceFromDepths(depthPC) : vec3(1.0);
    if (uDebugView == 2) inscatter = vec3(0.0);
    fragColor = vec4(surface * transmittance + inscatter, 1.0);
}
#endif
