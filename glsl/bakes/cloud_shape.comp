#version 430
// Cloud shape noise, compute path (GL >= 4.3); the model is in cloud_shape.glsl.
#include "cloud_shape.glsl"
#include "bake3d_compute.glsl"
