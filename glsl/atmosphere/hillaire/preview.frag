#version 330 core
// =============================================================================================
// Method 4 — a minimal composite showing how a scene calls hillaire_lookup.glsl (Hillaire 2020
// §5.3–5.4, §6): sky from the sky-view LUT (or the march from space), a grey Lambertian ground
// sphere lit by the sun through HillaireSunTransmittance, and the aerial perspective between the
// camera and the ground. No sun disk, no terrain: the planet scene does the real composite.
// Output: linear radiance (uSunIntensity units), alpha 1.
// Failure cases: those of hillaire_lookup.glsl; the ground distance comes from the model's
// GroundDistance (float32 sphere test), good to a few metres at grazing angles.
// =============================================================================================
#include "hillaire_lookup.glsl"

in vec2 vUV;
out vec4 fragColor;
uniform float uPreviewGroundAlbedo;   // 0.3

// The ground sphere where the pixel's ray meets it (lit, then the aerial perspective), else sky.
void main() {
    vec3 dir = CameraRayDirection(vUV);
    float tGround = GroundDistance(dir);
    vec3 L;
    if (tGround < 1.0e29) {
        vec3 p = dir * tGround;
        vec3 n = normalize(p - uEarthCenter);
        vec3 lit = uSunIntensity * HillaireSunTransmittance(p) * max(dot(n, uSunDir), 0.0)
                   * uPreviewGroundAlbedo / PI;
        vec4 ap = HillaireAerialPerspective(vUV, tGround);
        L = lit * HillaireTransmittance(tGround, dir) + ap.rgb;
    } else {
        L = HillaireSkyRadiance(dir);
    }
    fragColor = vec4(L, 1.0);
}
