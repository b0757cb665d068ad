#version 330 core
// =============================================================================================
// Method 4, pass 4 (fragment fallback, GL 3.3 / macOS) — the aerial-perspective volume
// (Hillaire 2020 §5.4). Renders a 2D target of W × (H·D) texels, slice k in rows [kH, (k+1)H),
// whose memory layout is exactly that of the W × H × D volume: the Python side copies it into
// the 3D textures through a pixel buffer, on the GPU. Each fragment marches its column up to its
// own slice (the compute path marches each column once). Model and failure cases:
// aerial_perspective.glsl.
// =============================================================================================
#include "hillaire_common.glsl"
#include "camera.glsl"
#include "aerial_perspective.glsl"

in vec2 vUV;
layout(location = 0) out vec4 outRayleighMultiple;
layout(location = 1) out vec4 outMie;

void main() {
    ivec2 p = ivec2(gl_FragCoord.xy);
    int slice = p.y / uHillaireApSize.y;
    ivec2 texel = ivec2(p.x, p.y - slice * uHillaireApSize.y);
    HillaireApColumn(texel, slice, outRayleighMultiple, outMie);
}
