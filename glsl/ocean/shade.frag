#version 330 core
// Deferred ocean, the shading pass (spec/000 §1.1–1.2; the equations in shading.glsl and
// waves.glsl): one pass over the screen that shades only the pixels the mesh or the far plane
// wrote (surface_inputs.frag, far_inputs.frag) — the same maths as the forward passes
// (surface.frag, far.frag): normals per pixel from the wave model at the rest point filtered
// for the footprint (the sine normal spec/000 eq. 2.2, the Gerstner B × T of spec/000 eq. 2.4,
// the FFT slopes of spec/000 eq. 2.11), Fresnel between the probe and the water body, the main
// light's glitter, foam, haze; from below, Snell's window over the scene copy.
// Which pixels: the quad lies on the far plane (z = 1) and is depth-tested GREATER, so pixels
// where nothing was drawn (depth still 1) are rejected before shading; a pixel some other
// object covers (kind 0 after the clear) is discarded on its first read. The FFT's textures are
// mip-filtered with the derivatives the inputs' pass stored (textureGrad), not this pass's:
// neighbouring pixels here may come from different triangles, or from the mesh and the far plane.
// Two programs: OCEAN_SEEN_FROM_ABOVE (the camera clearly above the water) compiles only the view
// from above; without it, the view from below and the per-pixel waterline are compiled in too.
// With floating objects (OCEAN_FLOATING), a boat's wake is evaluated per pixel (wake.glsl) or,
// with OCEAN_WAKE_MAP, read from the map wake_map.frag made per block of pixels.
// Failure cases guarded: the far plane's pixels (kind 2) are always shaded from above, with no
// crest term, as far.frag does; the view from below is decided per pixel exactly as in
// surface.frag (uViewMode, the waterline); the refracted lookup is clamped to the screen;
// negative radiance is clamped to 0.
in vec2 vUV;

uniform sampler2D uInputRel;   // (p − camera, η)
uniform sampler2D uInputSurf;  // (rest point − camera.xz, footprint, kind: 0 none, 1 mesh, 2 far)
uniform sampler2D uInputGrad;  // (d off / dx, d off / dy) where the inputs were rasterised
uniform float uSeaHs;          // significant wave height (m), for the crest term
uniform sampler2D uSceneCopy;  // the target before the ocean (sky, clouds), for the view from below
uniform vec2 uViewport;
uniform int uViewMode;         // 0 above the water, 1 below it, 2 near the surface: per pixel

uniform vec3 uCameraPos;

out vec4 fragColor;

#include "ocean/waves.glsl"
#include "ocean/shading.glsl"
#ifdef OCEAN_FLOATING  // a scene with floating objects: their wakes
#ifdef OCEAN_WAKE_MAP
// the wake's foam evaluated once per block of pixels (wake_map.frag), read back filtered
uniform sampler2D uWakeMap;
uniform int uWakeStride;  // screen pixels per texel side of uWakeMap

float WakeMapFoam() {
    float stride = float(uWakeStride);
    // texel i holds the pixel i·stride + stride/2 of its block: its centre maps to i + ½
    vec2 t = (gl_FragCoord.xy - float(uWakeStride / 2) - 0.5) / stride + 0.5;
    return texture(uWakeMap, t / vec2(textureSize(uWakeMap, 0))).r;
}
#else
#include "wake.glsl"
#endif
#endif

void main() {
    ivec2 px = ivec2(gl_FragCoord.xy);
    vec4 s = texelFetch(uInputSurf, px, 0);
    if (s.w < 0.5) discard;
    vec4 r = texelFetch(uInputRel, px, 0);
    vec4 grad = texelFetch(uInputGrad, px, 0);
    oceanOffDx = grad.xy;  // the FFT's mip filter, as the rasterising pass had it
    oceanOffDy = grad.zw;
    vec3 n;
    float foam, lost;
    OceanSurface(s.xy, s.z, n, foam, lost);
#ifdef OCEAN_FLOATING
#ifdef OCEAN_WAKE_MAP
    foam = max(foam, WakeMapFoam());  // a boat's wake, evaluated per block (wake_map.frag)
#else
    foam = max(foam, WakeFoam(s.xy));  // a boat's wake, left in world space (wake.glsl)
#endif
#endif
    vec3 v = normalize(-r.xyz);
    float crest = r.w / max(uSeaHs, 1e-3);
    vec3 c;
#ifdef OCEAN_SEEN_FROM_ABOVE
    // the camera clearly above the water (uViewMode 0): a program of its own, because a software
    // rasteriser runs a branch's code even when a uniform skips it (here: the view from below)
    c = OceanShadeAbove(r.xyz, n, v, foam, lost, crest);
#else
    // the mesh as surface.frag decides it; the far plane (kind 2) is always seen from above
    bool below = s.w < 1.5 && uViewMode == 1;
    if (uViewMode == 2) {
        below = s.w < 1.5 && OceanPixelStartsUnderwater(gl_FragCoord.xy / uViewport * 2.0 - 1.0,
                                                        uCameraPos.y);
    }
    if (!below) {
        c = OceanShadeAbove(r.xyz, n, v, foam, lost, crest);
    } else {
        vec2 uv = gl_FragCoord.xy / uViewport + n.xz * 0.05;
        vec3 behind = texture(uSceneCopy, clamp(uv, vec2(0.0), vec2(1.0))).rgb;
        c = OceanShadeBelow(n, v, behind, UnderwaterLight());
    }
#endif
    fragColor = vec4(max(c, vec3(0.0)), 1.0);
}
