#version 330 core
// =============================================================================================
// The planet's ground pass (spec/002 §5, the test scene; §3.3 the surfaces' colour): the
// analytic Earth and the space background (planet/surroundings.glsl) shaded once per frame into
// the G-buffer's colour where no mesh is (planet/ground.vert: the far plane, depth test '<='),
// so the per-method scattering pass (planet/composite.frag, SURFACES_IN_GBUFFER) reads every
// pixel's Color_original(O) with one texelFetch and its time is the atmosphere's alone: this is
// fixed per-pixel work every method paid alike, which compressed the methods' ratios (the
// thesis's 3.3–7×, §5). The position target gets w = 0 (not a mesh), its clear value.
// Equations: none of its own (Color_original; §1.4 attenuates it in the scattering pass).
// Failure cases: as planet/surroundings.glsl (the star lookup's asin clamped, no depth bias on
// the analytic ground, a seamless cubemap); pixels under a mesh fail the depth test and keep the
// mesh's colour; float32 at planet scale: camera-relative vectors only (model.glsl).
// =============================================================================================
#include "atmosphere/model.glsl"
#include "camera.glsl"

uniform vec3 uCameraLocal;   // camera in the local frame at the scene origin (m)

#include "atmosphere/optical_depth_lut.glsl"
#include "atmosphere/sun_transmittance.glsl"
#include "shadow.glsl"
#include "surroundings.glsl"

in vec2 vUV;
layout(location = 0) out vec4 outColor;
layout(location = 1) out vec4 outPosition;

void main() {
    outColor = vec4(SurroundingsColor(CameraRayDirection(vUV)), 1.0);
    outPosition = vec4(0.0);
}
