#version 430
// Inverse FFT along one axis of an N×N RGBA32F texture, one row (or column) per work group,
// in shared memory — the transform of spec/000 §1.1(d) (Tessendorf 2001, §3.1 "the FFT";
// Cooley–Tukey 1965), used by GpuFFT in app/gpu/fft.py when GL ≥ 4.3.
//
//   out[m] = Σ_k in[k]·e^{+2πi·k·m/N}          (= N·numpy.fft.ifft along the axis)
//
// Radix-2 decimation in time, in place: the N/2 invocations load the row in bit-reversed order,
// then log2 N butterfly stages of half-size h = 1, 2, …, N/2 each combine x[i0] and x[i1 = i0+h]
// as (a + w·b, a − w·b) with w = e^{+2πi·p/(2h)} = twiddle[p·N/(2h)], p = position in the
// block.  One shared row of N vec4 (16 KiB at N = 1024, half of a ping-pong Stockham's 32 KiB,
// which is exactly GL's guaranteed minimum and would leave no room) and one barrier per stage:
// in a stage each invocation reads and writes only its own pair.
//
// Defines (from app/gpu/fft.py): FFT_N (4…1024, a power of two), FFT_HALF_N = N/2, FFT_LOG2N.
// Failure cases guarded: twiddles come from a float64 table (no sin/cos of large float32
// angles); the stages are unrolled with #if, so every barrier() sits in main()'s top-level
// flow as GLSL 4.30 requires; a work group of FFT_N/2 ≤ 512 invocations stays inside GL's
// guaranteed 1024.
#ifndef FFT_N
#error FFT_N must be defined
#endif

layout(local_size_x = FFT_HALF_N) in;  // a literal: GLSL 4.30 takes no expression here
layout(rgba32f, binding = 0) uniform image2D uData;  // read and written in place
uniform sampler2D uTwiddle;  // N/2 × 1, RG32F: e^{+2πi·m/N}, m < N/2
uniform int uAxis;           // 0: transform along x (texel rows), 1: along z (texel columns)

#include "fft_common.glsl"

shared vec4 sLine[FFT_N];

int BitReversed(int i) {
    return int(bitfieldReverse(uint(i)) >> uint(32 - FFT_LOG2N));
}

ivec2 LineTexel(int line, int i) {
    return uAxis == 0 ? ivec2(i, line) : ivec2(line, i);
}

// One butterfly of the stage with half-size h, by invocation t < N/2.
void Butterfly(int t, int h) {
    int p = t & (h - 1);             // position inside the block of 2h
    int i0 = ((t - p) << 1) + p;     // block start (t/h)·2h plus p
    int i1 = i0 + h;
    vec2 w = texelFetch(uTwiddle, ivec2(p * (FFT_N / (2 * h)), 0), 0).xy;
    vec4 a = sLine[i0];
    vec4 b = ComplexMulPair(sLine[i1], w);
    sLine[i0] = a + b;
    sLine[i1] = a - b;
}

#define FFT_STAGE(h) memoryBarrierShared(); barrier(); Butterfly(t, h);

void main() {
    int line = int(gl_WorkGroupID.x);
    int t = int(gl_LocalInvocationID.x);
    const int halfN = FFT_HALF_N;
    sLine[BitReversed(t)] = imageLoad(uData, LineTexel(line, t));
    sLine[BitReversed(t + halfN)] = imageLoad(uData, LineTexel(line, t + halfN));
    FFT_STAGE(1)
    FFT_STAGE(2)
#if FFT_LOG2N > 2
    FFT_STAGE(4)
#endif
#if FFT_LOG2N > 3
    FFT_STAGE(8)
#endif
#if FFT_LOG2N > 4
    FFT_STAGE(16)
#endif
#if FFT_LOG2N > 5
    FFT_STAGE(32)
#endif
#if FFT_LOG2N > 6
    FFT_STAGE(64)
#endif
#if FFT_LOG2N > 7
    FFT_STAGE(128)
#endif
#if FFT_LOG2N > 8
    FFT_STAGE(256)
#endif
#if FFT_LOG2N > 9
    FFT_STAGE(512)
#endif
    memoryBarrierShared();
    barrier();
    imageStore(uData, LineTexel(line, t), sLine[t]);
    imageStore(uData, LineTexel(line, t + halfN), sLine[t + halfN]);
}
