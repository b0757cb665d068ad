#version 330 core
// Test probe for cloud model A (used by the model A tests): evaluates the functions of
// glsl/clouds/cloud_model.glsl per pixel on inputs read from three RGBA32F textures (A, B, C;
// one test case per texel), so each can be compared with its numpy twin in app/sim/clouds.py.
//   uProbeMode 0: (RoundBottom(pa), RoundTop(pa, mca), DensityBottom(pa), DensityTop(pa)),
//                 pa = A.x, mca = A.y
//              1: (Remap(A.x, A.y, A.z, A.w, B.x), HeightFraction(B.y, B.z, B.w),
//                  HeightDensity(C.x, C.y, C.z), saturate(C.w))
//              2: (CloudDensityFromSamples with detail, without detail, 0, 0): weather A, shape B,
//                  detail C.rgb, pa C.w, coverage and density from uniforms
//              3: (HG(A.x, A.y), Beer(A.z, A.w), Powder(A.z, A.w), InOutScatter(A.x, uniforms))
//              4: (RayBoxIntersect(A.xyz, B.xyz, uBoxMin, uBoxMax), 0, 0)
//              5: (hit, t0, t1, 0) of RaySphereIntersect(A.xyz, B.xyz, C.xyz, C.w)
#include "../clouds/cloud_model.glsl"

out vec4 fragColor;
uniform int uProbeMode;
uniform sampler2D uInputA;
uniform sampler2D uInputB;
uniform sampler2D uInputC;
uniform float uProbeCoverage;
uniform float uProbeDensity;
uniform vec4 uProbeScatter;      // in_s, out_s, ivo, cs_i
uniform float uProbeSilverExponent;
uniform vec3 uBoxMin;
uniform vec3 uBoxMax;

void main() {
    ivec2 px = ivec2(gl_FragCoord.xy);
    vec4 a = texelFetch(uInputA, px, 0), b = texelFetch(uInputB, px, 0);
    vec4 c = texelFetch(uInputC, px, 0);
    vec4 o = vec4(0.0);
    if (uProbeMode == 0) {
        o = vec4(RoundBottom(a.x), RoundTop(a.x, a.y), DensityBottom(a.x), DensityTop(a.x));
    } else if (uProbeMode == 1) {
        o = vec4(Remap(a.x, a.y, a.z, a.w, b.x), HeightFraction(b.y, b.z, b.w),
                 HeightDensity(c.x, c.y, c.z), saturate(c.w));
    } else if (uProbeMode == 2) {
        o = vec4(CloudDensityFromSamples(a, b, c.rgb, c.w, uProbeCoverage, uProbeDensity, true),
                 CloudDensityFromSamples(a, b, c.rgb, c.w, uProbeCoverage, uProbeDensity, false),
                 0.0, 0.0);
    } else if (uProbeMode == 3) {
        o = vec4(HenyeyGreenstein(a.x, a.y), Beer(a.z, a.w), Powder(a.z, a.w),
                 InOutScatter(a.x, uProbeScatter.x, uProbeScatter.y, uProbeScatter.z,
                              uProbeScatter.w, uProbeSilverExponent));
    } else if (uProbeMode == 4) {
        o = vec4(RayBoxIntersect(a.xyz, b.xyz, uBoxMin, uBoxMax), 0.0, 0.0);
    } else {
        vec2 t;
        bool hit = RaySphereIntersect(a.xyz, b.xyz, c.xyz, c.w, t);
        o = vec4(hit ? 1.0 : 0.0, t, 0.0);
    }
    fragColor = o;
}
