#version 330 core
// Ocean surface shading per pixel (spec/000 §1.1–1.2; see shading.glsl for the equations): the
// forward path (ocean.shading = forward), shading as the mesh is drawn; the deferred path writes
// the inputs (surface_inputs.frag) and shades them once per covered pixel (shade.frag).
// Normals come per pixel from the wave model at the interpolated rest point, filtered for the
// pixel footprint. Seen from below (the camera under a wave), Snell's window shows the scene
// behind (sky and clouds, a copy of the target) and total internal reflection the water.
// Equations (in waves.glsl): the sine normal spec/000 eq. 2.2, the Gerstner tangents
// spec/000 eq. 2.7 and spec/000 eq. 2.8 crossed as B × T (spec/000 eq. 2.4), the FFT normal
// from the spectral slopes of spec/000 eq. 2.11 (§1.1(d)).
// Failure cases guarded: normal aliasing at a distance (the footprint, floored at 1e-4 m,
// removes the waves the pixel cannot show and hands their slope variance to the glitter);
// a back face seen from above at grazing angles is a depth-test near-tie, not the underside
// (only uViewMode decides, per pixel near the surface: the waterline); the refracted lookup
// into the scene copy is clamped to the screen; negative radiance is clamped to 0; waves
// through a hull (a floating object's dry volume, dry_mask.glsl) are discarded; a boat's wake
// (wake.glsl) is foam left in world space, so it does not turn with the boat.
in vec2 vOff;
in vec3 vRel;
in float vHeight;

uniform float uSeaHs;          // significant wave height (m), for the crest term
uniform sampler2D uSceneCopy;  // the target before the ocean (sky, clouds), for the view from below
uniform vec2 uViewport;
uniform int uViewMode;  // 0 camera above the water, 1 below it, 2 near the surface: test per pixel
uniform float uCamNear;

uniform vec3 uCameraPos;

out vec4 fragColor;

#include "ocean/waves.glsl"
#include "ocean/shading.glsl"
#ifdef OCEAN_FLOATING  // a scene with floating objects: their wakes and dry volumes
#include "wake.glsl"
#include "dry_mask.glsl"
#endif

void main() {
#ifdef OCEAN_FLOATING
    if (InsideDryVolume()) discard;  // inside a hull: the deck stays dry
#endif
    float footprint = max(length(fwidth(vOff)), 1e-4);
    vec3 n;
    float foam, lost;
    OceanSurface(vOff, footprint, n, foam, lost);
#ifdef OCEAN_FLOATING
    foam = max(foam, WakeFoam(vOff));
#endif
    vec3 v = normalize(-vRel);
    vec3 c;
    // Seen from below only when the camera is under the water (a back face seen from above is a
    // depth-test near-tie at grazing angles, not the underside). Near the surface, the pixel's ray
    // starts on the near plane: below the water there → seen from below (the waterline).
    bool below = uViewMode == 1;
    if (uViewMode == 2) {
        below = OceanPixelStartsUnderwater(gl_FragCoord.xy / uViewport * 2.0 - 1.0, uCameraPos.y);
    }
    if (!below) {
        c = OceanShadeAbove(vRel, n, v, foam, lost, vHeight / max(uSeaHs, 1e-3));
    } else {
        vec2 uv = gl_FragCoord.xy / uViewport + n.xz * 0.05;
        vec3 behind = texture(uSceneCopy, clamp(uv, vec2(0.0), vec2(1.0))).rgb;
        c = OceanShadeBelow(n, v, behind, UnderwaterLight());
    }
    fragColor = vec4(max(c, vec3(0.0)), 1.0);
}
