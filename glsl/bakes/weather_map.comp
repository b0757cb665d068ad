#version 430
// Weather map, compute path (GL >= 4.3), baked as a one-slice volume; see weather_map.glsl.
#include "weather_map.glsl"
#include "bake3d_compute.glsl"
