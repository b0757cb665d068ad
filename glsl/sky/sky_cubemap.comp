#version 430
// Day–night sky into the environment cubemap (spec/000 §1.7, the thesis's reflection probe),
// run only when the hour or a sky parameter changed. GL ≥ 4.3; sky_face.frag is the path
// without compute shaders.
layout(local_size_x = 8, local_size_y = 8) in;
layout(rgba16f, binding = 0) writeonly uniform imageCube uCube;
uniform int uFaceSize;

#include "cubemap.glsl"
#include "sky_radiance.glsl"

void main() {
    ivec3 g = ivec3(gl_GlobalInvocationID);
    if (g.x >= uFaceSize || g.y >= uFaceSize) return;
    vec2 st = (vec2(g.xy) + 0.5) / float(uFaceSize) * 2.0 - 1.0;
    imageStore(uCube, g, vec4(SkyRadiance(CubemapFaceDirection(g.z, st)), 1.0));
}
