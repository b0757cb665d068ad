#version 330 core
// The thesis's geometry-shader grass (spec/003 §2.9 a, "Custom/Grass/GeometryGrass", kept
// although the thesis rejected it for the final scene), program ProgramSpec("grass/blades_gs",
// GS_SECTIONS, GS_MAX_VERTICES): this file + blades_gs.geom + blades_gs.frag. This stage only
// passes each root triangle's vertex on (object space = world space: the village's root
// triangles are placed on the island by app/sim/grass.py); the geometry stage builds the
// pyramid and moves it in the wind (spec/003 eq. 7.1, spec/003 eq. 7.2, spec/003 eq. 7.3,
// spec/003 eq. 7.4: see grass_wind.glsl).
// Failure cases guarded: none arise here (no transform); the geometry stage guards the rest.
in vec3 in_position;

out vec3 gPosition;

void main() {
    gPosition = in_position;
    gl_Position = vec4(in_position, 1.0);
}
