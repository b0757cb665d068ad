#version 330 core
// Test probe for the amortised layer (tests/gl/test_amortise.py; beyond the theses, after
// Schneider 2015): a stand-in "march" of glsl/common/amortise.glsl with a known answer, so the
// resolve (glsl/common/amortise_resolve.frag) can be compared with the numpy twins of
// app/sim/amortise.py. At the pixel AmortisedPixel() marches, with the opaque scene's distance
// d along its ray (from uSceneDepth):
//   d < uProbeOpaque (an object in front of the layer):  layer (0, 0, 0, 1)
//   otherwise: layer (0.5 + 0.5 dir, 0.3 + 0.2 (dir.x + 1)), dir the ray's direction (so the
//   layer is fixed in the world: a turning camera sees it move)
// and aux AmortiseAux(uProbeOpaque, d).
// Failure cases: none of its own — those guarded are the included files' (their headers).
#include "../common/camera.glsl"
#include "../common/amortise.glsl"

uniform sampler2D uSceneDepth;
uniform float uCamNear;
uniform float uCamFar;
uniform float uProbeOpaque;

layout(location = 0) out vec4 fragColor;
layout(location = 1) out vec4 outAux;

void main() {
    ivec2 pixel = AmortisedPixel();
    vec2 uv = AmortisedUV(pixel);
    vec3 dir = CameraRayDirection(uv);
    float depth = texelFetch(uSceneDepth, pixel, 0).r;
    float d = 1.0e30;
    if (depth < 1.0) {
        float z = depth * 2.0 - 1.0;
        float viewZ = 2.0 * uCamNear * uCamFar / (uCamFar + uCamNear - z * (uCamFar - uCamNear));
        d = viewZ / max(dot(dir, uCamForward), 1.0e-6);
    }
    fragColor = d < uProbeOpaque ? vec4(0.0, 0.0, 0.0, 1.0)
                                 : vec4(0.5 + 0.5 * dir, 0.3 + 0.2 * (dir.x + 1.0));
    outAux = AmortiseAux(uProbeOpaque, d);
}
