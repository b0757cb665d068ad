// Driver for baking a function into a 3D texture with a compute shader (GL ≥ 4.3).
// The including file defines vec4 BakeValue(vec3 uvw), uvw = texel centre in [0, 1]³.
// bake3d_fragment.glsl is the same bake one slice at a time, for contexts without compute.
//
// uBakeZOffset lets the driver (app/gpu/bake.py, bake_volume(chunk_slices=...)) dispatch the
// volume in chunks of z slices — for a progress indication and to keep each dispatch short
// (a watchdog may kill long ones). It is 0 (the whole volume at once) unless set.
// Work groups are 8 x 8 x 1 (one tile of one slice; app/gpu/bake.py LOCAL_SIZE): on llvmpipe
// they bake about twice as fast as 4 x 4 x 4, and a chunk can be any number of slices.
layout(local_size_x = 8, local_size_y = 8, local_size_z = 1) in;
layout(rgba32f, binding = 0) writeonly uniform image3D uBakeTarget;
uniform ivec3 uBakeSize;
uniform int uBakeZOffset;

void main() {
    ivec3 g = ivec3(gl_GlobalInvocationID) + ivec3(0, 0, uBakeZOffset);
    if (any(greaterThanEqual(g, uBakeSize))) return;
    imageStore(uBakeTarget, g, BakeValue((vec3(g) + 0.5) / vec3(uBakeSize)));
}
