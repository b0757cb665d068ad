#version 330 core
// One triangle that covers the screen on the far plane (window depth exactly 1, the depth
// buffer's clear value): depth-tested with "less or equal", it shades only the pixels nothing
// has drawn into. vUV is (0,0) bottom-left to (1,1) top-right, as in fullscreen.vert.
out vec2 vUV;

void main() {
    vec2 p = vec2((gl_VertexID << 1) & 2, gl_VertexID & 2);
    vUV = p;
    gl_Position = vec4(p * 2.0 - 1.0, 1.0, 1.0);
}
