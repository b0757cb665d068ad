#version 330 core
// =============================================================================================
// Cloud Model B, view march (spec/000 §1.6; spec/000 §A.7 and §A.8, the fragment program of
// "Clouds.shader"). The model (density, phase, light march) and its header are in
// clouds_b_model.glsl.
//
// Output: rgb = lightEnergy · SunColor (the in-scattered light), a = transmittance. The effect
// composites it over the scene with blending, out = background·a + rgb — the thesis's
//   §A.8   return float4(background·transmittance + lightEnergy·_SunColor, 1)
// without reading the target it writes (see glsl/common/layer_composite.frag).
//
// Depth: the thesis's depth = LinearEyeDepth(depth)·|viewVector| with viewVector.z = −1, i.e.
// distance along the ray = eye depth / dot(rayDir, cameraForward). A depth of 1 (cleared) is the
// far plane. Failure cases: rays that miss the box (dstInside = 0) and pixels whose geometry is
// nearer than the box return (0, 1) exactly; the loop stops at uMaxSteps.
//
// Jitter (beyond the thesis, whose fixed step bands — its failure case): the amortised march
// (glsl/common/amortise.glsl, app/render/amortise.py) starts each ray a blue-noise fraction of
// a step past the box entry, AmortiseJitter(pixel), and uJitterReference does the same with a
// fixed phase for the bench's reference (the thesis's march averaged over its offsets);
// otherwise the first sample is at the entry, as the thesis has it. At location 1 the
// amortised march's aux: the transmittance-weighted distance of the cloud met,
// each step's distance weighted by the light that step takes away, over the whole 1 − T taken
// away; and the opaque scene's distance.
//
// Aerial perspective (beyond the thesis; uHazeDistance = 0 turns it off, the thesis): light
// scattered at distance s along the ray reaches the eye by the fraction f = exp(−s/H), the rest
// of the cloud's opacity is replaced by the air's horizon colour (the sky probe sampled just
// above the horizon in the ray's azimuth, as the ocean's haze): rgb = Σ E_i f_i·SunColor +
// Σ (T_{i−1} − T_i)(1 − f_i)·horizon. Without a probe the faded part turns transparent instead
// (a += Σ (T_{i−1} − T_i)(1 − f_i)), so far clouds melt into the sky behind them.
// =============================================================================================
#include "camera.glsl"
#include "clouds_b_model.glsl"
#include "amortise.glsl"

uniform sampler2D uSceneDepth;  // window-space depth of the opaque scene ([0, 1], 1 = far)
uniform bool uHasDepth;         // false: the target has no depth buffer (everything is far)
uniform float uCameraNear;
uniform float uCameraFar;
uniform vec3 uLightDir;         // unit vector toward the sun (the main light)
uniform vec3 uLightColor;       // _SunColor: the main light's radiance
uniform float uHazeDistance;    // @param 0 [0, 200000] step=100 unit=m §1.6 beyond the thesis:
                                //   aerial perspective, distance over which the clouds fade into
                                //   the horizon's haze (0 = off, the thesis)
uniform samplerCube uHazeEnvironment;  // the sky probe (no sun disk): the horizon's colour
uniform bool uHasHazeEnvironment;      // false: the faded part turns transparent
uniform float uHazeLods;               // mip levels of the probe − 1
uniform bool uAmortised;               // an amortised march: blue-noise jitter
uniform bool uJitterReference;         // the same jitter at uJitterPhase (the bench's reference)

in vec2 vUV;
layout(location = 0) out vec4 fragColor;
layout(location = 1) out vec4 outAux;  // amortised march: (cloud distance, scene distance)

// Distance along the unit view ray to the opaque scene at a full-resolution pixel.
float SceneDistance(vec3 rayDir, ivec2 pixel) {
    if (!uHasDepth) return 3.0e38;
    float depth = texelFetch(uSceneDepth, pixel, 0).r;
    float zNdc = depth * 2.0 - 1.0;
    float eyeDepth = 2.0 * uCameraNear * uCameraFar
                     / (uCameraFar + uCameraNear - zNdc * (uCameraFar - uCameraNear));
    return eyeDepth / max(dot(rayDir, uCamForward), 1.0e-6);
}

void main() {
    if (AmortisePadding()) discard;  // a banded grid's padding
    ivec2 pixel = AmortisedPixel();  // itself, or one pixel of each block (amortised)
    vec3 rayOrigin = uCameraPos;
    vec3 rayDir = CameraRayDirection(AmortisedUV(pixel));
    float sceneDistance = SceneDistance(rayDir, pixel);
    outAux = AmortiseAux(AMORTISE_FAR, sceneDistance);

    vec2 hit = CloudsBRayBoxDistance(uBoundsMin, uBoundsMax, rayOrigin, rayDir);
    float dstToBox = hit.x;
    float dstInsideBox = hit.y;
    vec3 entryPoint = rayOrigin + rayDir * dstToBox;

    float pixelAngle = 2.0 * uTanHalfFov / uAmortiseFullSize.y;  // radians per pixel
    float cosAngle = dot(rayDir, uLightDir);
    float phaseValue = CloudsBPhase(cosAngle);

    float stepSize = uFixedStepSize;
    float dstLimit = min(sceneDistance - dstToBox, dstInsideBox);
    float dstTravelled = (uAmortised || uJitterReference) ? AmortiseJitter(pixel) * stepSize
                                                          : 0.0;
    float transmittance = 1.0;
    float tSum = 0.0;  // Σ step distance × transmittance removed: the cloud's distance (aux)
    float lightEnergy = 0.0;
    float haze = 0.0;  // opacity handed to the air (aerial perspective)
    float invHaze = uHazeDistance > 0.0 ? 1.0 / uHazeDistance : 0.0;
    for (int i = 0; i < uMaxSteps; i++) {
        if (dstTravelled >= dstLimit) break;
        vec3 rayPos = entryPoint + rayDir * dstTravelled;
        gNoiseFootprint = (dstToBox + dstTravelled) * pixelAngle * uCloudScale * 0.001;
        float density = CloudsBSampleDensity(rayPos);
        if (density > 0.0) {
            float fade = exp(-(dstToBox + dstTravelled) * invHaze);
            float lightTransmittance = CloudsBLightAtPos(rayPos, uLightDir);
            lightEnergy += density * stepSize * transmittance * lightTransmittance * phaseValue
                         * CloudsBPowder(density) * fade;
            float before = transmittance;
            transmittance *= CloudsBBeer(density * stepSize * uLightAbsortionCloud);
            haze += (before - transmittance) * (1.0 - fade);
            tSum += (before - transmittance) * (dstToBox + dstTravelled);
            if (transmittance < 0.01) break;  // early exit (spec/000 §A.8)
        }
        dstTravelled += stepSize;
    }
    if (transmittance < 0.9999) outAux.x = tSum / (1.0 - transmittance);
    vec3 rgb = lightEnergy * uLightColor;
    if (haze > 0.0) {
        if (uHasHazeEnvironment) {
            vec3 h = normalize(vec3(rayDir.x, 0.0, rayDir.z) + vec3(0.0, 0.02, 0.0));
            rgb += haze * max(textureLod(uHazeEnvironment, h, min(2.0, uHazeLods)).rgb, vec3(0.0));
        } else {
            transmittance += haze;
        }
    }
    fragColor = vec4(rgb, transmittance);
}
