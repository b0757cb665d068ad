#version 330 core
// Cloud detail noise, one z slice per full-screen pass (no compute needed); see cloud_detail.glsl.
#include "cloud_detail.glsl"
#include "bake3d_fragment.glsl"
