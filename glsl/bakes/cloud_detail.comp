#version 430
// Cloud detail noise, compute path (GL >= 4.3); the model is in cloud_detail.glsl.
#include "cloud_detail.glsl"
#include "bake3d_compute.glsl"
