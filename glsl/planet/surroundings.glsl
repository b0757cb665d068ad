// =============================================================================================
// What a planet pixel sees when no mesh covers it (spec/002 §5, the test scene): the analytic
// Earth sphere — land and sea from gradient fBm over the sphere (planet/ground_noise.glsl,
// baked or live), lit as the thesis's texture (§3.3: Color_original) or with Lambert, the shadow
// map and the sun's transmittance from the optical-depth LUT (§1.8) — or space: the star field on
// the universe sphere and, beyond the thesis, the sun's disk.
// Equations: none of the thesis's (the surface colour Color_original(O) the scattering pass
// attenuates, §1.4); diffuse = min(V, n·l) as the meshes' Phong (planet/surface.frag).
// Used by planet/ground.frag (the default: shaded once into the G-buffer's colour, outside the
// per-method pass) and by planet/composite.frag without SURFACES_IN_GBUFFER (the earlier path).
// Needs atmosphere/model.glsl, atmosphere/optical_depth_lut.glsl,
// atmosphere/sun_transmittance.glsl, planet/shadow.glsl and uCameraLocal; includes
// planet/sky_irradiance.glsl (the ambient: k_a, or beyond the thesis the sky's irradiance).
// Failure cases: the asin of the star lookup is clamped; the analytic ground takes no shadow-map
// depth bias (it cannot shadow itself, see GroundColor); the baked noise's cubemap is seamless
// (GL_TEXTURE_CUBE_MAP_SEAMLESS), so face edges do not show; the cap's gnomonic coordinates are
// guarded against n.y → 0 (the far cubemap is used there).
// =============================================================================================
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

#include "sky_irradiance.glsl"

uniform sampler2D uStarTex;
uniform float uStarIntensity;
uniform bool uSunDisk;
uniform float uSunDiskCos;        // cos of the sun's angular radius
uniform float uSunDiskRadiance;
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
    vec3 sun = uKd * diffuse * SunTransmittanceAt(rel);
    return uSkyAmbient ? albedo * (uKd * SkyIrradiance(n) + sun) : albedo * (uKa + sun);
}

// Color_original of a pixel no mesh covers, along the unit camera ray dir: the ground at the
// distance GroundDistance(dir) (model.glsl), or the background where the ray misses the planet.
vec3 SurroundingsColor(vec3 dir) {
    float dist = GroundDistance(dir);
    return dist < 1.0e29 ? GroundColor(dir * dist) : Background(dir);
}
