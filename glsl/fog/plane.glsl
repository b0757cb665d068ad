// The ground fog plane's cutoff and opacity (spec/003 §2.11 a, the thesis's Custom/Fog shader as
// its public repository writes it): the fragment shader modulates the cutoff with Unity's
// _SinTime.x = sin(t/8), so the fog thins and returns, and subtracts it from the texture's alpha
// (diffuse.a = tex.a − cutoff). Numpy twin: app/sim/fog.py (plane_cutoff, plane_alpha).
// Failure cases guarded: the cutoff saturated (a negative _SinTime gives 0, never a negative
// cutoff that would add opacity); the alpha clamped to [0, 1] as an 8-bit target clamps it (a
// float target would otherwise blend with a negative alpha, brightening what lies behind).

// saturate(_Cutoff·_SinTime.x)
float FogPlaneCutoff(float cutoff, float time) {
    return clamp(cutoff * sin(time / 8.0), 0.0, 1.0);
}

// saturate(a − cutoff), times the ground mask (0 where the ground drops away below the plane)
float FogPlaneAlpha(float textureAlpha, float cutoff, float mask) {
    return clamp(textureAlpha - cutoff, 0.0, 1.0) * clamp(mask, 0.0, 1.0);
}
