#version 330 core
// Test probe for the banded layout of a march grid (tests/gl/test_amortise.py; beyond the
// theses): each fragment of the banded target writes the grid texel it marches
// (AmortiseGridTexel, glsl/common/amortise.glsl) and whether it is padding, so the test can
// check that every texel is marched once and that a 4 × 4 block holds one grid row.
// Failure cases: none of its own — those guarded are the included file's (its header).
#include "../common/amortise.glsl"

layout(location = 0) out vec4 fragColor;

void main() {
    ivec2 t = AmortiseGridTexel();
    fragColor = vec4(vec2(t), AmortisePadding() ? 1.0 : 0.0, 1.0);
}
