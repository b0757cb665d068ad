#version 430
// Bake of the wood's distortion noise (compute path); see wood_noise_bake.glsl.
#include "wood_noise_bake.glsl"
#include "bake3d_compute.glsl"
