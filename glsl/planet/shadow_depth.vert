#version 330 core
// Depth-only pass from the sun (spec/002 §4.2, the shadow-map pipeline).
in vec3 in_position;
uniform mat4 uLightViewProj;
void main() { gl_Position = uLightViewProj * vec4(in_position, 1.0); }
