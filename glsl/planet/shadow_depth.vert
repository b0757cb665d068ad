#version 330 core
// Depth-only pass from the sun (spec/002 §4.2, the shadow-map pipeline; the map itself,
// spec/002 §3.1: orthographic, rendered only when the sun direction changes).
// Equations: none (a light view × orthographic projection of local-frame positions).
// Failure cases: positions stay in the scene's local frame (metres from its origin, not from
// the planet centre), so float32 depth holds; points outside the light's box are clipped here
// and count as lit when the map is read (shadow.glsl), which also applies the bias.
in vec3 in_position;
uniform mat4 uLightViewProj;
void main() { gl_Position = uLightViewProj * vec4(in_position, 1.0); }
