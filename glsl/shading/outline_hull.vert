#version 330 core
// The inverted-hull outline of spec/003 §2.13 (variation "geometry-shader shell"), program
// ProgramSpec("shading/outline_hull"): this file + outline_hull.geom + outline_hull.frag. This
// stage only moves each vertex to world space and picks the normal to extrude along; the
// geometry stage emits the extruded triangle (see its header for the width's units).
//
// Interface: in_position (vec3), in_normal (vec3, the faceted shading normal), in_smooth_normal
// (vec3, one normal per position: smooth_normals of app.sim.lab_meshes.LabMesh, its own vertex
// buffer); uModel (rotation, translation, uniform scale); uSmoothNormals (bool).
//
// Failure cases guarded: the thesis's per-vertex normals are split at hard edges, so the shell
// tears open there on low-poly meshes (spec/003 §2.13, Fig. 133b); uSmoothNormals extrudes
// along the smoothed normal instead, which every copy of a vertex shares, so the shell stays
// closed (the fix). Normals go through mat3(uModel), exact only for the rotation, translation
// and uniform scale the lab uses.
in vec3 in_position;
in vec3 in_normal;
in vec3 in_smooth_normal;

uniform mat4 uModel;
uniform bool uSmoothNormals;  // extrude along in_smooth_normal (closed shell) instead of in_normal

out vec3 gWorldPos;
out vec3 gWorldNormal;

void main() {
    vec4 world = uModel * vec4(in_position, 1.0);
    gWorldPos = world.xyz;
    gWorldNormal = mat3(uModel) * (uSmoothNormals ? in_smooth_normal : in_normal);
    gl_Position = world;
}
