#version 330 core
// Bake of the wood's distortion noise, one slice per pass (path without compute shaders).
#include "wood_noise_bake.glsl"
#include "bake3d_fragment.glsl"
