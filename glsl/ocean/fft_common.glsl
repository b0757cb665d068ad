// Complex arithmetic for the ocean's inverse FFT (app/gpu/fft.py).
//
// A complex number is a vec2 (re, im).  A texel of the FFT textures holds two of them,
// (re0, im0, re1, im1), which go through the transform side by side with the same twiddles.
// The twiddle tables are built in float64 on the CPU (angles from integers, 2π·m/N) and stored
// as float32, so no sin/cos of a large float32 argument happens anywhere in the transform.

vec2 ComplexMul(vec2 a, vec2 b) {
    return vec2(a.x * b.x - a.y * b.y, a.x * b.y + a.y * b.x);
}

// Both complex numbers of a texel times the same complex w.
vec4 ComplexMulPair(vec4 pair, vec2 w) {
    return vec4(ComplexMul(pair.xy, w), ComplexMul(pair.zw, w));
}
