// =============================================================================================
// Fresnel reflectance and Snell refraction — the project's one Fresnel (spec/003 §2.7, the
// thesis's §5.3; Schlick 1994). An include of functions; numpy twin app/sim/optics.py
// (fresnel_exact, fresnel_schlick, schlick_fresnel, refract_direction; one function each,
// tests/unit/test_fresnel.py compares them on a grid within 1e-5).
//   η = n1/n2                                 spec/003 eq. 5.21 (n1 the medium of the incident ray)
//   cos θ2 = sqrt(1 − η² sin²θ1)              spec/003 eq. 5.22
//   r = η(v + n cos θ1) − n cos θ2            spec/003 eq. 5.23
//                                             (v toward the surface, n facing v's origin)
//   Rs = ((n1 cos θ1 − n2 cos θ2)/(n1 cos θ1 + n2 cos θ2))²     spec/003 eq. 5.24
//   Rp = ((n1 cos θ2 − n2 cos θ1)/(n1 cos θ2 + n2 cos θ1))²     spec/003 eq. 5.25
//   R  = ½(Rs + Rp)                           spec/003 eq. 5.26
//   c  = ((n1 − n2)/(n1 + n2))²               spec/003 eq. 5.28
//   R  = c + (1 − c)(1 − cos θ)^5             spec/003 eq. 5.27, spec/003 eq. 5.29 (Schlick)
// Beyond the thesis (which only goes from air into the denser medium): for n1 > n2 Schlick's
// cos θ is that of the transmitted ray, cos θ2 (Schlick's own advice, and what the ocean's
// Snell window in glsl/ocean/shading.glsl does), and R = 1 past the critical angle; with
// cos θ1 instead the curve would miss total internal reflection entirely.
// Failure cases guarded: cos θ1 clamped into [0, 1]; the square root of spec/003 eq. 5.22
// taken only when 1 − η² sin²θ1 > 0 (otherwise total internal reflection: R = 1, the direction
// reflected); the denominators of spec/003 eq. 5.24 and spec/003 eq. 5.25 kept above 1e-20
// (n1 = n2 at grazing gives 0/0: R = 0 there, the limit for equal media); no NaN at cos θ1 = 0.
// =============================================================================================

// Schlick's Fresnel reflectance F = F0 + (1 − F0)(1 − cos θ)^5, cos θ clamped into [0, 1]
// (spec/003 eq. 5.27). Twin: schlick_fresnel in app/sim/optics.py.
float SchlickFresnel(float f0, float cosTheta) {
    float m = 1.0 - clamp(cosTheta, 0.0, 1.0);
    float m2 = m * m;
    return f0 + (1.0 - f0) * m2 * m2 * m;
}

// Exact unpolarised dielectric reflectance from medium n1 into n2 at incidence cos θ1
// (spec/003 eq. 5.24, spec/003 eq. 5.25, spec/003 eq. 5.26); 1 under total internal reflection.
float FresnelExact(float cosI, float n1, float n2) {
    float c1 = clamp(cosI, 0.0, 1.0);
    float eta = n1 / n2;
    float sinT2 = eta * eta * (1.0 - c1 * c1);
    if (sinT2 > 1.0) return 1.0;
    float c2 = sqrt(1.0 - sinT2);                             // spec/003 eq. 5.22
    float rs = (n1 * c1 - n2 * c2) / max(n1 * c1 + n2 * c2, 1e-20);
    float rp = (n1 * c2 - n2 * c1) / max(n1 * c2 + n2 * c1, 1e-20);
    return clamp(0.5 * (rs * rs + rp * rp), 0.0, 1.0);
}

// Schlick's approximation from n1 into n2 (spec/003 eq. 5.28, spec/003 eq. 5.29): cos θ1 when
// n1 ≤ n2; for n1 > n2 the transmitted cos θ2, and 1 past the critical angle (see above).
float FresnelSchlick(float cosI, float n1, float n2) {
    float r = (n1 - n2) / (n1 + n2);
    float c = r * r;
    float cosT = clamp(cosI, 0.0, 1.0);
    if (n1 > n2) {
        float eta = n1 / n2;
        float sinT2 = eta * eta * (1.0 - cosT * cosT);
        if (sinT2 > 1.0) return 1.0;
        cosT = sqrt(1.0 - sinT2);
    }
    return SchlickFresnel(c, cosT);
}

// Refracted direction of v (unit, toward the surface) through the interface of normal n (unit,
// facing v's origin), η = n1/n2 (spec/003 eq. 5.22, spec/003 eq. 5.23). Under total internal
// reflection returns reflect(v, n) and tir = true. Inputs are normalised here.
vec3 RefractDirection(vec3 v, vec3 n, float eta, out bool tir) {
    vec3 vv = normalize(v);
    vec3 nn = normalize(n);
    float c1 = clamp(-dot(vv, nn), -1.0, 1.0);
    float k = 1.0 - eta * eta * (1.0 - c1 * c1);
    tir = k < 0.0;
    if (tir) return reflect(vv, nn);
    return normalize(eta * (vv + nn * c1) - nn * sqrt(k));
}
