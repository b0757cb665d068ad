#version 330 core
// Weather map, one full-screen pass (no compute needed); see weather_map.glsl.
#include "weather_map.glsl"
#include "bake3d_fragment.glsl"
