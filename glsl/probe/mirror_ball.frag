#version 330 core
// Mirror ball lit by the environment cubemap — the maritime thesis's reflection probe
// (spec/000 §1.7, fig. 4.10: the scene with and without the probe), on the simplest surface
// that shows it: an analytic sphere hit by the camera ray.
// Reflectance: Schlick's Fresnel F = F0 + (1 − F0)(1 − cos θ)^5.
// Failure cases: rays that miss or graze the sphere (discriminant ≤ 0) are discarded; the
// reflection lookup uses an explicit LOD so roughness does not depend on screen derivatives.
#include "math.glsl"
#include "fresnel.glsl"
#include "camera.glsl"

in vec2 vUV;
out vec4 fragColor;

uniform samplerCube uEnvironment;
uniform float uEnvironmentLods;
uniform vec3 uMainLightDir;
uniform vec3 uMainLightRadiance;

uniform vec3 uBallCenter;   // @param (0, 3, -12) [-100, 100] §1.7 mirror ball centre (m)
uniform float uBallRadius;  // @param 2 [0.1, 20] step=0.1 unit=m §1.7 mirror ball radius
// F0 is Schlick's reflectance at normal incidence; Roughness blurs the reflection through
// the cubemap's mip level; the base colour is the diffuse one under the main light; without
// the probe the ball is the thesis's "without probe" case.
uniform float uFresnelF0; // @param 0.6 [0, 1] step=0.01 §1.7 reflectance at normal incidence
                          // (Schlick F0)
uniform float uRoughness; // @param 0 [0, 1] step=0.01 §1.7 blur of the reflection (cubemap mip
                          // level)
uniform vec3 uBaseColor; // @param (0.05, 0.05, 0.06) [0, 1] color §1.7 diffuse colour under the
                         // main light
uniform bool uUseProbe; // @param true §1.7 reflect the environment cubemap (off: the thesis's
                        // "without probe")

void main() {
    vec3 d = CameraRayDirection(vUV);
    vec3 oc = uCameraPos - uBallCenter;
    float b = dot(oc, d);
    float c = dot(oc, oc) - uBallRadius * uBallRadius;
    float h = b * b - c;
    if (h <= 0.0) discard;
    float t = -b - sqrt(h);
    if (t <= 0.0) discard;
    vec3 n = normalize(oc + t * d);
    float cosTheta = saturate(dot(-d, n));
    float fresnel = SchlickFresnel(uFresnelF0, cosTheta);
    vec3 r = reflect(d, n);
    vec3 env = uUseProbe ? textureLod(uEnvironment, r, uRoughness * uEnvironmentLods).rgb
                         : vec3(0.0);
    vec3 diffuse = uBaseColor * uMainLightRadiance * saturate(dot(n, uMainLightDir));
    fragColor = vec4(fresnel * env + (1.0 - fresnel) * diffuse, 1.0);
}
