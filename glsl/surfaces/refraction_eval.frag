#version 330 core
// GPU probe of glsl/common/fresnel.glsl and glsl/surfaces/refraction.glsl (spec/003 §2.7) for
// the tests: the functions evaluated at the points of uPoints (one per pixel) so they can be
// compared with the numpy twin app/sim/optics.py.
// Equations: spec/003 eq. 5.22 to 5.29 (in the includes).
//   uEvalMode 0: p = (cos θ1, n1, n2): (FresnelExact, FresnelSchlick, SchlickFresnel(p.y, p.x), 0)
//             1: p = incident direction v: (RefractDirection(v, uNormal, uEta), tir)
//             2: p = point on the sphere (uSphereCentre, uSphereRadius), v from uEye:
//                (RefractSphere(uInterfaces, …), tir)
//             3: p = (x, y, strength): (DistortNormal(uNormal, uTangent, uBitangent, xy, s),
//                RefractionLod(p.x, p.y))
//             4: p = (ndc x, ndc y, 0): the refraction harness — a camera at uEye looking down −z
//                (uFov), the sphere refracts the code-made cubemap uEnv (uInterfaces
//                interfaces), misses look it up directly: (colour, tir)
// Failure cases guarded: as the includes; the points texture is read with texelFetch.
#include "../common/fresnel.glsl"
#include "refraction.glsl"

uniform sampler2D uPoints;
uniform samplerCube uEnv;
uniform int uEvalMode;
uniform vec3 uNormal;
uniform vec3 uTangent;
uniform vec3 uBitangent;
uniform float uEta;
uniform vec3 uEye;
uniform vec3 uSphereCentre;
uniform float uSphereRadius;
uniform int uInterfaces;
uniform float uFov;

out vec4 fragColor;

void main() {
    vec3 p = texelFetch(uPoints, ivec2(gl_FragCoord.xy), 0).xyz;
    bool tir = false;
    if (uEvalMode == 0) {
        fragColor = vec4(FresnelExact(p.x, p.y, p.z), FresnelSchlick(p.x, p.y, p.z),
                         SchlickFresnel(p.y, p.x), 0.0);
    } else if (uEvalMode == 1) {
        vec3 r = RefractDirection(p, uNormal, uEta, tir);
        fragColor = vec4(r, tir ? 1.0 : 0.0);
    } else if (uEvalMode == 2) {
        vec3 r = RefractSphere(uInterfaces, p, normalize(p - uEye), uSphereCentre,
                               uSphereRadius, uEta, tir);
        fragColor = vec4(r, tir ? 1.0 : 0.0);
    } else if (uEvalMode == 3) {
        fragColor = vec4(DistortNormal(uNormal, uTangent, uBitangent, p.xy, p.z),
                         RefractionLod(p.x, p.y));
    } else {
        float f = tan(0.5 * uFov);
        vec3 v = normalize(vec3(p.x * f, p.y * f, -1.0));
        vec3 o = uEye - uSphereCentre;
        float b = dot(o, v);
        float disc = b * b - (dot(o, o) - uSphereRadius * uSphereRadius);
        vec3 look = v;
        if (disc > 0.0 && -b - sqrt(disc) > 0.0) {
            vec3 hit = uEye + (-b - sqrt(disc)) * v;
            look = RefractSphere(uInterfaces, hit, v, uSphereCentre, uSphereRadius, uEta, tir);
        }
        fragColor = vec4(textureLod(uEnv, look, 0.0).rgb, tir ? 1.0 : 0.0);
    }
}
