#version 330 core
// Cloud shape noise, one z slice per full-screen pass (no compute needed); see cloud_shape.glsl.
#include "cloud_shape.glsl"
#include "bake3d_fragment.glsl"
