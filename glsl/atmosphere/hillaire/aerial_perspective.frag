#version 330 core
// =============================================================================================
// Method 4, pass 4 (fragment fallback, GL 3.3 / macOS) — the aerial-perspective volume
// (Hillaire 2020 §5.4). Renders a 2D target of W × (H·n) texels, slice uHillaireApFirstSlice + k
// in rows [kH, (k+1)H), whose memory layout is exactly that of n slices of the W × H × D volume:
// the Python side copies it into the 3D textures through a pixel buffer, on the GPU (n is as
// many slices as the texture-size limit allows). Each fragment marches its column up to its own
// slice (the compute path marches each column once); both give the same numbers. Model and
// failure cases: aerial_perspective.glsl.
// =============================================================================================
#include "hillaire_common.glsl"
#include "camera.glsl"
#include "aerial_perspective.glsl"

in vec2 vUV;
layout(location = 0) out vec4 outRayleighMultiple;
layout(location = 1) out vec4 outMie;
uniform int uHillaireApFirstSlice;

void main() {
    ivec2 p = ivec2(gl_FragCoord.xy);
    int row = p.y / uHillaireApSize.y;
    ivec2 texel = ivec2(p.x, p.y - row * uHillaireApSize.y);
    HillaireApColumn(texel, uHillaireApFirstSlice + row, outRayleighMultiple, outMie);
}
