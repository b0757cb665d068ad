#version 330 core
// The toon water seen from inside (spec/003 §2.10; beyond the thesis, whose camera never goes
// under the water): a full-screen pass, blended over the image before the surface is drawn,
// that tints every pixel whose view ray starts under the water as water.frag tints the
// refraction — WaterRefraction(scene, lit colour, α, w) with w the thickness weight
// 1 − exp(−I·t) of the water the ray crosses: t the distance to the scene point, or to the
// surface when the ray leaves the water first. Blending (src α, 1 − src α) with
// src = (lit colour, 1 − α·(1 − w)) gives exactly mix(mix(colour, scene, α), colour, w).
// Per pixel, a ray starts under the water when its point on the near plane is below the tide's
// level, so a camera at the surface sees the split line where the near plane crosses it.
// Failure cases guarded: rays parallel to the surface (no exit: the scene's distance alone); the
// scene depth 1 (nothing drawn) read as the far plane; pixels starting above the water are
// discarded, so a camera above the surface changes nothing; Depth Fog? off leaves w = 0.
#include "water.glsl"
#include "camera.glsl"

in vec2 vUV;

uniform sampler2D uSceneDepth;   // a copy of the image's window depth
uniform vec2 uNearFar;           // the camera's near and far planes [m]
uniform float uSeaLevel;
uniform float uTime;
uniform vec3 uLightDir;
uniform vec3 uLightRadiance;
uniform vec3 uAmbient;

out vec4 fragColor;

void main() {
    float level = TideLevel(uSeaLevel, uTideHeight, uTime);
    vec3 d = CameraRayDirection(vUV);
    float along = max(dot(d, uCamForward), 1e-6);   // view depth per metre of ray
    vec3 start = uCameraPos + d * (uNearFar.x / along);
    if (start.y >= level) discard;
    float tScene = ViewDepth(texelFetch(uSceneDepth, ivec2(gl_FragCoord.xy), 0).r, uNearFar)
                   / along;
    float t = d.y > 1e-6 ? min(tScene, (level - uCameraPos.y) / d.y) : tScene;
    float w = uDepthFog ? FogWeightThickness(t, uWaterFogIntensity) : 0.0;
    vec3 light = WaterLight(uColor, uLightDir, uLightRadiance, uAmbient);
    fragColor = vec4(light, 1.0 - clamp(uRefraction, 0.0, 1.0) * (1.0 - w));
}
