#version 330 core
// The thesis's final grass: crossed billboards (spec/003 §2.9 b, "Custom/Grass-CrossBillboard"
// and the GrassGenerator), program ProgramSpec("grass/billboard"): this file +
// billboard.frag. One instance per unit; a unit is uPlanes planes crossed through its centre,
// θ_k = uAngleStart + k·uAngleStep with uAngleStep = 180°/n (the document's θ_k = k·180°/n, or
// the repository's −90° + Δ/2 + k·Δ: −60°, 0°, 60° for three planes, Fig. 102's Angle −60).
//
// Billboard (this stage does it, and the wind): the centre P_c is the unit's model origin,
// half the quad above its root; the plane faces the camera's *position* (Fig. 96b):
//   v = normalize(camera − P_c), y the Billboard Y vector: the camera's up u, (0, 1, 0), or
//   ŷ = u + (0, 1, 0)                                          spec/003 eq. 7.7
//   normalised                                                 spec/003 eq. 7.8
//   r = normalize(y × v)  (the camera's right for a unit in the middle of the view)
//   R_y(θ) = [[cos θ, 0, sin θ], [0, 1, 0], [−sin θ, 0, cos θ]] spec/003 eq. 7.9
//   r' = R_y(θ)·r                                              spec/003 eq. 7.10
//   n' = r' × y   (the thesis's r' × u)                        spec/003 eq. 7.11
//   n' recomputed for each rotated plane                       spec/003 eq. 7.12
//   x' = P_c + s·x·r'                                          spec/003 eq. 7.5
//   y' = P_c + s·y·y                                           spec/003 eq. 7.6
// with (x, y) ∈ [−½, ½]² the corner and s the quad's side ((0.25 + Scale) m: Unity's 10-unit
// plane at 0.1 m per unit, times the repository's 0.25 + _Scale). Object-space offsets ignore
// the object's scale, as the thesis notes: the size is the user's. Then the wind of the unit
// (grass_wind.glsl: spec/003 eq. 7.13, spec/003 eq. 7.14, spec/003 eq. 7.15, spec/003 eq. 7.16,
// spec/003 eq. 7.17), its _Seed and _SinSeed shared by every plane of the unit, so the planes
// move together and the texture is not torn (the thesis's reason for per-unit seeds).
//
// With culling on (the effect's tiles), a unit shrinks to nothing over the last 20 % of the
// draw distance, so the tiles beyond it vanish without a visible edge.
// Failure cases guarded: y ∥ v (a camera straight above a unit with y = (0, 1, 0): y × v = 0)
// falls back to the camera's right; a camera exactly at P_c uses the direction opposite the
// camera's forward; Billboard Y = camera up seen from above turns the tufts about the view
// axis (the thesis's Fig. 98a artefact, kept on purpose in that mode); the texture's v runs 0 at
// the root to 1 at the top, so the wind's v² keeps the root still.
#include "math.glsl"
#include "fog.glsl"
#include "grass_wind.glsl"

invariant gl_Position;  // the two-pass draw's passes must write and test equal depths

in vec2 in_corner;    // (x, y) ∈ [−½, ½]²
in float in_plane;    // k = 0 … 3
in vec3 in_centre;    // the unit's root on the ground (per instance)
in vec4 in_unit;      // _Seed, _SinSeed, texture index 0..2, 0 (per instance)
in vec3 in_tint;      // the unit's ripeness tint (per instance)

uniform mat4 uViewProj;
uniform vec3 uCameraPos;
uniform vec3 uCamRight;
uniform vec3 uCamUp;
uniform int uBillboardY;      // 0 camera up, 1 world up, 2 their normalised mean
uniform float uAngleStart;    // θ_0 [degrees]
uniform float uAngleStep;     // 180°/n [degrees]
uniform float uSize;          // the quad's side s [m]
uniform bool uFade;           // culling on: the units shrink to nothing over the last 20 % of
uniform float uDrawDistance;  // the draw distance [m] (beyond it their tile is not drawn)
uniform float uBbBend; // @param 0.4 [0, 1] step=0.01 §2.9 billboard wind: the tip's offset per unit
                       // of intensity, in quad sides (the thesis's scale is illegible)
uniform float uBbSteady; // @param 1 [0, 5] step=0.1 §2.9 billboard wind: the steady part of (steady
                         // + s) — 1 the document's (1 + A·sin) form, 3 the repository's (3 +
                         // movement)

out vec4 vWorldPos;   // xyz world position, w the fog factor of the vertex
out vec3 vNormal;
out vec2 vUV;
flat out vec3 vTint;

// The rotated plane's frame: r' (spec/003 eq. 7.10), y and n' (spec/003 eq. 7.11).
void BillboardFrame(vec3 centre, float thetaDeg, out vec3 r, out vec3 y, out vec3 n) {
    vec3 back = SafeNormalize(cross(uCamRight, uCamUp), vec3(0.0, 0.0, 1.0));  // −forward
    vec3 v = SafeNormalize(uCameraPos - centre, back);
    vec3 u = SafeNormalize(uCamUp, vec3(0.0, 1.0, 0.0));
    if (uBillboardY == 0) y = u;
    else if (uBillboardY == 1) y = vec3(0.0, 1.0, 0.0);
    else y = SafeNormalize(u + vec3(0.0, 1.0, 0.0), vec3(0.0, 1.0, 0.0));
    vec3 r0 = SafeNormalize(cross(y, v), SafeNormalize(uCamRight, vec3(1.0, 0.0, 0.0)));
    float th = radians(thetaDeg);
    float c = cos(th), s = sin(th);
    r = vec3(c * r0.x + s * r0.z, r0.y, -s * r0.x + c * r0.z);
    n = cross(r, y);
}

void main() {
    float size = uSize;
    if (uFade) {
        size *= 1.0 - smoothstep(0.8 * uDrawDistance, uDrawDistance,
                                 length(in_centre - uCameraPos));
    }
    vec3 centre = in_centre + vec3(0.0, 0.5 * size, 0.0);
    vec3 r, y, n;
    BillboardFrame(centre, uAngleStart + in_plane * uAngleStep, r, y, n);
    vec3 p = centre + size * in_corner.x * r + size * in_corner.y * y;
    float v = in_corner.y + 0.5;
    p += GrassBillboardWind(v, in_unit.x, in_unit.y, size, uBbBend, uBbSteady);
    gl_Position = uViewProj * vec4(p, 1.0);
    vWorldPos = vec4(p, FogVertexFactor(gl_Position));
    vNormal = n;
    vUV = vec2((clamp(in_unit.z, 0.0, 2.0) + in_corner.x + 0.5) / 3.0, v);
    vTint = in_tint;
}
