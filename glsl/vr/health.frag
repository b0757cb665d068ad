#version 330 core
// The FixedHealth ring's fragment stage (spec/003 §2.15, Custom/VR/FixedHealth): e = 2·uv − 1,
// its angle counter-clockwise from the screen's right, step = 360°/Lives, section =
// floor(angle/step), a gap of 5 % of a step on each side of every boundary (the repository's
// saturate((a − t)(step − a − t)) in degrees²), Color Full where Remaining·step > section·step
// else Color Empty, × the UI texture's red mask (kept above ½, as the repository) × the gap;
// Visibility multiplies alpha; blended SrcAlpha/OneMinusSrcAlpha. Twin: ring_fragment in
// app/sim/vr.py.
// Failure cases guarded: the document's acos(ê·(1, 0)) covers only 0–180° (the lower half
// mirrors the upper: uAngleMode 1 reproduces it) — the default takes the angle by quadrant over
// 0–360° as the repository does, with exact degrees (the repository's 57 for 180/π leaves a
// 0.5° step at each quadrant); e = 0 (the centre, outside the ring) gets angle 0, not a NaN;
// Lives < 1 is taken as 1 and Remaining is clamped to [0, Lives].

in vec2 vUV;
out vec4 fragColor;

// uRingMask: the UI texture, the ring's shape in red (app.sim.vr.ring_mask_texture).
uniform sampler2D uRingMask;
uniform float uVisibility; // @param 0.5 [0, 1] step=0.01 §2.15 Visibility (Fig. 145): multiplies
                           // the ring's alpha (0 hidden, 1 opaque)
uniform int uLives; // @param 20 [1, 64] §2.15 Lives: the ring's sections (Fig. 145's inspector: 20;
                    // Fig. 146 shows 8)
uniform float uRemaining; // @param 12.35 [0, 64] step=1 §2.15 Remaining (Fig. 145: 12.35): sections
                          // below it are full; clamped to Lives
uniform vec3 uColorFull; // @param (1, 0, 0) [0, 1] color §2.15 Color Full (the repository's
                         // material: red)
uniform vec3 uColorEmpty; // @param (1, 0.706, 0.706) [0, 1] color §2.15 Color Empty (the
                          // repository's material: pale red)
uniform int uAngleMode;       // 0 by quadrant (0–360°), 1 the document's acos (0–180°)

const float GAP_FRACTION = 0.05;
const float DEGREES = 57.29577951308232;

// The angle of e (the ring's coordinates, [−1, 1]²) in degrees counter-clockwise from the
// screen's right: by quadrant over [0, 360) or, with uAngleMode 1, the document's acos over
// [0, 180]. The centre (|e| < 1e-6) gets 0, not a NaN.
float RingAngle(vec2 e) {
    float r = length(e);
    if (r < 1e-6) {
        return 0.0;
    }
    if (uAngleMode == 1) {
        return acos(clamp(e.x / r, -1.0, 1.0)) * DEGREES;
    }
    float a = atan(e.y, e.x) * DEGREES;
    a = a < 0.0 ? a + 360.0 : a;
    return a >= 360.0 ? 0.0 : a;
}

void main() {
    int lives = max(uLives, 1);
    float remaining = clamp(uRemaining, 0.0, float(lives));
    vec2 e = 2.0 * vUV - 1.0;
    float angle = RingAngle(e);
    float stepDeg = 360.0 / float(lives);
    float section = floor(angle / stepDeg);
    float within = angle - section * stepDeg;
    float t = GAP_FRACTION * stepDeg;
    float gap = clamp((within - t) * ((stepDeg - within) - t), 0.0, 1.0);
    float red = texture(uRingMask, vUV).r;
    float mask = red > 0.5 ? red : 0.0;
    float m = mask * gap;
    vec3 colour = (remaining * stepDeg > section * stepDeg) ? uColorFull : uColorEmpty;
    fragColor = vec4(colour * m, uVisibility * m);
}
