#version 330 core
// =============================================================================================
// Bake of the analytic Earth's land/sea noise f(n) (ground_noise.glsl; spec/002 §5, Perlin
// 2002) at each texel's centre direction, for two textures the scattering pass reads instead of
// 5 octaves per pixel (planet/composite.frag, GroundNoise):
//   uFace 0..5  one face of a cubemap over the whole sphere (common/cubemap.glsl: the GL face
//               order and orientation), the coarse one;
//   uFace 6     the cap about the scene's origin (the +y pole of the local frame): a gnomonic
//               square, n ∝ (s · tan α, 1, t · tan α), st ∈ [−1, 1]², half-angle α = uCapAngle —
//               finer texels where every view of the scene looks (from space at 300 km the
//               horizon is 17° from the pole).
// Equations: none of the thesis (the noise is the scene's, ground_noise.glsl).
// Failure cases guarded: texel centres, not corners (st = 2 uv − 1 at the centres the full-
// screen pass rasterises), so a face's edge texels match their neighbours across the seam
// within one texel's interpolation; the R32F target keeps f's sign and small values exact.
// =============================================================================================
#include "ground_noise.glsl"
#include "cubemap.glsl"

in vec2 vUV;
out vec4 fragColor;

uniform int uFace;         // 0..5: +X, −X, +Y, −Y, +Z, −Z; 6: the cap about +y
uniform float uCapTan;     // tan of the cap's half-angle

void main() {
    vec2 st = vUV * 2.0 - 1.0;
    vec3 n = uFace < 6 ? CubemapFaceDirection(uFace, st)
                       : normalize(vec3(st.x * uCapTan, 1.0, st.y * uCapTan));
    fragColor = vec4(GroundNoiseFbm(n), 0.0, 0.0, 1.0);
}
