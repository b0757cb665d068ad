#version 330 core
// Sails and flag, fragment stage — the maritime thesis's cloth shader (spec/000 §1.5): the
// Alpha texture cuts the cloth's shape, holes and tears (discarded fragments), the two-colour
// Pattern picks ColorA or ColorB; the cloth is lit by the main light on both sides, with a
// translucency share reaching the unlit side (beyond the thesis), and by the sky's
// environment cubemap (the reflection probe of spec/000 §1.7) sampled at the normal at its
// most blurred level. Output: linear radiance.
//   colour = Pattern ≥ ½ ? ColorA : ColorB
//   L = colour · (E · max(n·l, 0) + Translucency · E · max(−n·l, 0)
//                 + env(n) + Translucency · env(−n))
// Failure cases guarded: the back of the cloth is lit as its front (the normal is flipped by
// gl_FrontFacing, corrected for a mirroring model matrix); the pattern is thresholded, so
// filtering never blends ColorA and ColorB (unlit, every pixel is one of the two); the alpha
// test uses 0.5, so a filtered hole edge is cut once; a zero interpolated normal (two opposite
// vertex normals) falls back to up instead of a NaN.
in vec3 vWorldPos;
in vec3 vWorldNormal;
in vec2 vUV;
out vec4 fragColor;

uniform sampler2D uAlpha;        // R8: 1 cloth, 0 hole
uniform sampler2D uPattern;      // R8: 1 ColorA, 0 ColorB
uniform vec3 uColorA;            // linear
uniform vec3 uColorB;
uniform float uTranslucency;     // share of the light transmitted to the unlit side
uniform vec3 uMainLightDir;      // toward the light, world
uniform vec3 uMainLightRadiance;
uniform samplerCube uEnvironment;
uniform float uEnvironmentLods;  // mip levels of the cubemap − 1
uniform mat4 uModel;
uniform bool uUnlit;             // output the pattern colour only (the tests' view)

void main() {
    if (texture(uAlpha, vUV).r < 0.5) discard;
    vec3 colour = texture(uPattern, vUV).r >= 0.5 ? uColorA : uColorB;
    if (uUnlit) {
        fragColor = vec4(colour, 1.0);
        return;
    }
    vec3 n = vWorldNormal;
    float len2 = dot(n, n);
    n = len2 > 1e-20 ? n * inversesqrt(len2) : vec3(0.0, 1.0, 0.0);
    bool mirrored = determinant(mat3(uModel)) < 0.0;
    if (gl_FrontFacing == mirrored) n = -n;  // the side seen
    float cosL = dot(n, uMainLightDir);
    vec3 direct = uMainLightRadiance * (max(cosL, 0.0) + uTranslucency * max(-cosL, 0.0));
    vec3 ambient = textureLod(uEnvironment, n, uEnvironmentLods).rgb
                 + uTranslucency * textureLod(uEnvironment, -n, uEnvironmentLods).rgb;
    fragColor = vec4(colour * (direct + ambient), 1.0);
}
