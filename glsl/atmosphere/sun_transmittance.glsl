// Sunlight reaching a point: the transmittance toward the sun from the optical-depth LUT
// (spec/002 §1.8), used to light surfaces (beyond the thesis: surfaces redden at sunset).
// Needs model.glsl and optical_depth_lut.glsl.
// Transmittance from a camera-relative point to the sun (0 where the planet hides the sun).
vec3 SunTransmittanceAt(vec3 rel) {
    vec3 fromCentre = rel - uEarthCenter;
    float r = length(fromCentre);
    return TransmittanceFromDepths(OpticalDepthToSun(r - uBottomRadius,
                                                     dot(fromCentre / r, uSunDir)));
}
