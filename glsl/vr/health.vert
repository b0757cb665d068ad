#version 330 core
// The FixedHealth ring's vertex stage (spec/003 §2.15, Custom/VR/FixedHealth, queue Overlay+2):
// the one head-locked element the thesis allows in VR. The clip position is written directly,
// spec/003 eq. 9.1 and spec/003 eq. 9.2:
//   x = 2(X + s·obj_x) − 1        y = ar·(2(Y + s·obj_y) − 1)
// on Unity's built-in Plane mesh (obj in [-5, 5]²): X, Y the ring's centre in [0, 1] of the
// viewport, s the Element Size (the viewport's width per unit of the Plane: the ring is 10·s of
// the width across). Erratum (twin app/sim/vr.py): the document's ar = height/width scales the
// centre too and squashes the ring into an ellipse; the repository's width/height is round but
// off-centre; the default (uAspectForm 0) applies W/H to the offset only, so the ring is round
// and centred at (X, Y)·viewport; 1 and 2 reproduce the two published forms.
// Failure cases guarded: a zero-size viewport (its aspect clamped away from 0 and ∞); depth is
// not written (z = 0, and the pass draws with the depth test off: ZTest Always).

in vec2 in_position;   // the Plane mesh's (x, z), in [-5, 5]
out vec2 vUV;          // (0, 0) bottom-left of the quad, +u right, +v up on screen

uniform float uElementSize; // @param 0.014 [0, 1] step=0.001 §2.15 Element Size (Fig. 145): the
                            // viewport's width per unit of the 10-unit Plane mesh, so the ring
                            // spans 10× this of the width
uniform float uScreenX; // @param 0.666 [0, 1] step=0.001 §2.15 Screen X (Fig. 145): the ring's
                        // centre, fraction of the viewport's width from its left
uniform float uScreenY; // @param 0.579 [0, 1] step=0.001 §2.15 Screen Y (Fig. 145): the ring's
                        // centre, fraction of the viewport's height from its bottom
uniform vec2 uViewport;      // the image's width and height [px]
uniform int uAspectForm;     // 0 corrected, 1 the document's h/w, 2 the repository's w/h

const float PLANE_HALF = 5.0;

void main() {
    vUV = in_position / (2.0 * PLANE_HALF) + 0.5;
    float wOverH = clamp(uViewport.x / max(uViewport.y, 1.0), 1e-4, 1e4);
    float x = 2.0 * (uScreenX + uElementSize * in_position.x) - 1.0;   // spec/003 eq. 9.1
    float y;
    if (uAspectForm == 0) {
        y = 2.0 * (uScreenY + uElementSize * wOverH * in_position.y) - 1.0;  // spec/003 eq. 9.2
    } else {
        float ar = uAspectForm == 1 ? 1.0 / wOverH : wOverH;
        y = ar * (2.0 * (uScreenY + uElementSize * in_position.y) - 1.0);  // spec/003 eq. 9.2
    }
    gl_Position = vec4(x, y, 0.0, 1.0);
}
