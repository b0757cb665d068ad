// =============================================================================================
// Ray intersections with boxes and spheres (spec/001 §1.9 and Annex C; spec/000 §A.4;
// spec/002 §2.4 item 2): distances t along origin + t·dir.
//
// Failure cases guarded: axis-parallel rays (a direction component below 1e-20 in magnitude is
// replaced by ±1e-20 with its sign, +1e-20 for zero, so a ray parallel to a slab is inside it for
// all t or for none and no 0·inf NaN appears); planet-sized spheres (c = |o − C|² − R² is
// formed as (|o − C| − R)(|o − C| + R), and the roots as q = −(b + sign(b)√disc), t = q and
// c/q, so neither root cancels); misses are decided on the discriminant, not on its root
// (spec/001 erratum 7).
// Numpy twin: app/sim/optics.py (ray_box, ray_sphere).
// =============================================================================================

// Slab method: (t_near, t_far), unclamped (either may be negative: behind the origin). The ray
// hits the box when t_far >= max(t_near, 0).
vec2 RayBoxIntersect(vec3 origin, vec3 dir, vec3 boxMin, vec3 boxMax) {
    const float tiny = 1.0e-20;
    vec3 safeDir = mix(dir, mix(vec3(-tiny), vec3(tiny), step(vec3(0.0), dir)),
                       lessThan(abs(dir), vec3(tiny)));
    vec3 inv = 1.0 / safeDir;
    vec3 t0 = (boxMin - origin) * inv;
    vec3 t1 = (boxMax - origin) * inv;
    vec3 tmin = min(t0, t1), tmax = max(t0, t1);
    return vec2(max(max(tmin.x, tmin.y), tmin.z), min(min(tmax.x, tmax.y), tmax.z));
}

// Ray–sphere for a unit direction: false on a miss (t = (-1, -2)); else t.x <= t.y, either
// may be negative (the sphere, or part of it, behind the origin).
bool RaySphereIntersect(vec3 origin, vec3 dir, vec3 centre, float radius, out vec2 t) {
    vec3 oc = origin - centre;
    float dist = length(oc);
    float b = dot(oc, dir);
    float c = (dist - radius) * (dist + radius);
    float disc = b * b - c;
    if (disc < 0.0) { t = vec2(-1.0, -2.0); return false; }
    float s = sqrt(disc);
    float q = -(b + (b >= 0.0 ? s : -s));
    float other = q != 0.0 ? c / q : -b;
    t = vec2(min(q, other), max(q, other));
    return true;
}
