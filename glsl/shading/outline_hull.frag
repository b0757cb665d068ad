#version 330 core
// The inverted-hull outline of spec/003 §2.13: the fragment stage returns the outline colour
// (the thesis's shader returns _OutlineColor; no lighting). See outline_hull.geom for the
// extrusion and its width.
// Failure cases: none here — a constant colour (the shell's failures are the geometry's, listed
// in outline_hull.vert and outline_hull.geom).
uniform vec3 uOutlineColor;  // linear

out vec4 fragColor;

void main() { fragColor = vec4(uOutlineColor, 1.0); }
