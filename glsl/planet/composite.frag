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
// SHADOW_COMPARE_MANUAL (shadow.glsl).
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
#ifdef GROUND_NOISE_BAKED
// f(n) of planet/ground_noise.glsl baked at texel centres (planet/ground_noise_bake.frag): the
// fine cap about the scene's origin where n falls in its gnomonic square, else the coarse cubemap.
uniform sampler2D uGroundNoiseCap;
uniform samplerCube uGroundNoise;
uniform float uGroundCapTan;        // tan of the cap's half-angle
float GroundNoise(vec3 n) {
    vec2 g = n.xz / (max(n.y, 1.0e-6) * uGroundCapTan);
    float near = texture(uGroundNoiseCap, g * 0.5 + 0.5).r;
    float far = texture(uGroundNoise, n).r;
    return n.y > 0.0 && max(abs(g.x), abs(g.y)) < 1.0 ? near : far;
}
#else
#include "ground_noise.glsl"
float GroundNoise(vec3 n) { return GroundNoiseFbm(n); }
#endif

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
#include "atmosphere/inscatter.glsl"
#if METHOD == 4
#include "atmosphere/hillaire/hillaire_lookup.glsl"
#endif

in vec2 vUV;
out vec4 fragColor;

uniform sampler2D uGColor;
uniform sampler2D uGPosition;
uniform sampler2D uStarTex;
uniform float uStarIntensity;
uniform bool uSunDisk;
uniform float uSunDiskCos;        // cos of the sun's angular radius
uniform float uSunDiskRadiance;
uniform float uUniverseRadius;    // method 1 integrates to this sphere for rays into space
uniform vec3 uUniverseCenter;     // its centre relative to the camera: the Earth's, or 0
uniform int uDebugView;           // 0 final, 1 in-scattering on black, 2 out-scattering on white
uniform int uGroundShading;       // 0 texture only, 1 Lambert + shadows + sun transmittance
uniform float uKa;
uniform float uKd;

vec3 Background(vec3 dir) {
    vec2 uv = vec2(atan(dir.x, dir.z) / TWO_PI, asin(ClampCosine(dir.y)) / HALF_PI);
    float s = texture(uStarTex, uv * 2.0).r;
    vec3 c = vec3(saturate(s * s * s * 3.0) * uStarIntensity);
    if (uSunDisk && dot(dir, uSunDir) > uSunDiskCos) c += vec3(uSunDiskRadiance);
    return c;
}

// Method 1's end of a ray into space: where it leaves the universe sphere (0 if it misses it).
float UniverseDistance(vec3 dir) {
    vec2 t;
    return RaySphereIntersect(vec3(0.0), dir, uUniverseCenter, uUniverseRadius, t) ? max(t.y, 0.0)
                                                                                    : 0.0;
}

// The analytic Earth: land and sea from gradient fBm over the sphere (baked, or live), the scene
// origin on land.
vec3 GroundColor(vec3 rel) {
    vec3 n = normalize(rel - uEarthCenter);
    vec3 local = rel + uCameraLocal;
    float nearOrigin = exp(-dot(local.xz, local.xz) / (2.0 * 16000.0 * 16000.0));
    float f = GroundNoise(n);
    float land = smoothstep(-0.02, 0.02, f + 0.6 * nearOrigin - 0.05);
    vec3 albedo = mix(vec3(0.02, 0.05, 0.09), vec3(0.2, 0.24, 0.11), land);
    if (uGroundShading == 0) return albedo;
    float nl = max(dot(n, uSunDir), 0.0);
    // No depth bias: the analytic ground is not in the shadow map, so it cannot shadow itself, and
    // any bias only detaches the meshes' shadows from them (0.0004 of the 60 km depth range is 24 m
    // along the light — more than most of the city's boxes are wide).
    float diffuse = min(ShadowVisibility(local, 0.0), nl);
    return albedo * (uKa + uKd * diffuse * SunTransmittanceAt(rel));
}

void main() {
    ivec2 px = ivec2(gl_FragCoord.xy);
    vec4 gpos = texelFetch(uGPosition, px, 0);
    vec3 dir = CameraRayDirection(vUV);
    vec3 surface;
    float dist;
    bool space = false;
    if (gpos.w > 0.5) {
        dist = length(gpos.xyz);
        dir = gpos.xyz / dist;
        surface = texelFetch(uGColor, px, 0).rgb;
    } else {
        dist = GroundDistance(dir);
        if (dist < 1.0e29) {
            surface = GroundColor(dir * dist);
        } else {
            space = true;
            surface = Background(dir);
        }
    }
    if (uDebugView == 1) surface = vec3(0.0);
    if (uDebugView == 2) surface = vec3(1.0);

    vec3 inscatter;
    vec3 transmittance;
#if METHOD == 4
    if (space) {
        inscatter = HillaireSkyRadiance(dir);
        vec2 seg = AtmosphereSegment(dir, 1.0e30);
        transmittance = seg.y > seg.x ? HillaireTransmittance(seg.y, dir) : vec3(1.0);
    } else {
        inscatter = HillaireAerialPerspectiveAlongRay(vUV, dir, dist).rgb;
        transmittance = HillaireTransmittance(dist, dir);
    }
#else
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
#endif
    if (uDebugView == 2) inscatter = vec3(0.0);
    fragColor = vec4(surface * transmittance + inscatter, 1.0);
}
