#version 330 core
// A slow cascade of the FFT ocean between its snapshots (spec/000 §1.1(e); Tessendorf 2001): the
// textures the surface samples — displacement (λD_x, η, λD_z, J), derivatives and foam — as the
// linear interpolation of two snapshots A (at t_a) and B (at t_a + T), computed ahead of time
// (app/effects/ocean/schedule.py): out = A + w·(B − A), w = (t − t_a)/T. Each mode evolves as
// e^{iωt} (spec/000 eq. 2.11), so the blend is short of the true phasor by 2·sin²(ωT/4) of its
// amplitude at mid-interval; T is chosen so that stays within the slope tolerance
// (app/sim/ocean.py refresh_period). With CASCADE_RESAMPLE, the same pass copies a cascade's foam
// into a grid of another size (the view changed its N): filtered lookups of the same tile.
// Failure cases guarded: texelFetch at integer texels when the sizes match (no filtering, so
// w = 0 returns A and w = 1 returns B exactly); w is clamped to [0, 1] on the CPU; the resample
// reads level 0 at the texel centre of the new grid with the tile's wrap (the textures repeat).
uniform sampler2D uDispA;
uniform sampler2D uDispB;
uniform sampler2D uDerivA;
uniform sampler2D uDerivB;
uniform sampler2D uFoamA;
uniform sampler2D uFoamB;
uniform float uWeight;  // w in [0, 1]
uniform int uN;         // size of the grid written

layout(location = 0) out vec4 oDisp;
layout(location = 1) out vec4 oDeriv;
layout(location = 2) out vec4 oFoam;

vec4 Read(sampler2D s) {
#ifdef CASCADE_RESAMPLE
    return textureLod(s, gl_FragCoord.xy / float(uN), 0.0);
#else
    return texelFetch(s, ivec2(gl_FragCoord.xy), 0);
#endif
}

void main() {
    oDisp = mix(Read(uDispA), Read(uDispB), uWeight);
    oDeriv = mix(Read(uDerivA), Read(uDerivB), uWeight);
    oFoam = vec4(mix(Read(uFoamA).r, Read(uFoamB).r, uWeight));
}
