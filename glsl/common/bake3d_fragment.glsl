// Driver for baking one z slice of a 3D texture with a fragment shader (no compute needed).
// The including file defines vec4 BakeValue(vec3 uvw); see bake3d_compute.glsl.
out vec4 fragColor;
uniform ivec3 uBakeSize;
uniform int uBakeSlice;

void main() {
    fragColor = BakeValue(vec3(gl_FragCoord.xy, float(uBakeSlice) + 0.5) / vec3(uBakeSize));
}
