#version 330 core
// The outline G-buffer (spec/003 §2.14: the post-process outline the thesis left as future
// work), program ProgramSpec("shading/gbuffer"): the lab's objects' view-space normal and
// linear view depth, for the screen-space edge detector (edges.frag), in a cheap pass of its own
// so the detector does not depend on the surface pass.
// Interface: in_position, in_normal (the shading normal); uModel, uView, uProj.
// Failure cases guarded: normals through mat3(uView · uModel), exact for the rigid motions and
// uniform scales the lab uses; the depth is the linear view distance along −z, not the
// non-linear depth buffer (a relative threshold on it means the same near and far).
in vec3 in_position;
in vec3 in_normal;

uniform mat4 uModel;
uniform mat4 uView;
uniform mat4 uProj;

out vec3 vViewNormal;
out float vViewDepth;

void main() {
    vec4 view = uView * uModel * vec4(in_position, 1.0);
    vViewNormal = mat3(uView) * mat3(uModel) * in_normal;
    vViewDepth = -view.z;
    gl_Position = uProj * view;
}
