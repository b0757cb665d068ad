// Driver for baking a function into a 3D texture with a compute shader (GL ≥ 4.3).
// The including file defines vec4 BakeValue(vec3 uvw), uvw = texel centre in [0, 1]³.
// bake3d_fragment.glsl is the same bake one slice at a time, for contexts without compute.
layout(local_size_x = 4, local_size_y = 4, local_size_z = 4) in;
layout(rgba32f, binding = 0) writeonly uniform image3D uBakeTarget;
uniform ivec3 uBakeSize;

void main() {
    ivec3 g = ivec3(gl_GlobalInvocationID);
    if (any(greaterThanEqual(g, uBakeSize))) return;
    imageStore(uBakeTarget, g, BakeValue((vec3(g) + 0.5) / vec3(uBakeSize)));
}
