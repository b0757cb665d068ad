// A boat's wake as foam: trail samples P left in world space, each a Kelvin ring (centre
// P + d·U·a/4, radius U·a/4) brightest at its cusp (cos = 1/3 to the travel direction d, from the
// centre, so the envelope is the 19.47° wedge) and a wash band along the path as wide as the
// beam (Kelvin 1887; twin: app/sim/wake.py).
// Positions are relative to the camera (folded on the CPU in float64), like the ocean's rest
// points. Failure cases guarded: no samples or a point outside the trail's bounds gives 0 after
// one test (uWakeBounds; a software rasteriser still runs the loop's first pass, masked, for a
// block of such points); a zero distance gives no NaN (the cosine's denominator is floored); a
// drifting boat paints nothing (the speed ramp).
#define WAKE_MAX 64
uniform int uWakeCount;               // 0: no wake
uniform int uWakeFirst;               // the samples this pass evaluates: uWakeFirst …
uniform int uWakeEnd;                 // … uWakeEnd − 1 (the wake map's chunks; else 0, count)
uniform vec4 uWakeBounds;             // (x min, z min, x max, z max), camera-relative
uniform vec4 uWakeSample[WAKE_MAX];   // (x − camera.x, z − camera.z, age s, speed m/s)
uniform vec2 uWakeDir[WAKE_MAX];      // unit direction of travel (x, z)
uniform vec4 uWakeShape;              // (beam m, cusp half-width m, spacing s, wash spread)
uniform vec3 uWakeLife;               // (cusp life s, wash life s, strength)

float WakeSmooth(float e0, float e1, float x) {
    float t = clamp((x - e0) / (e1 - e0), 0.0, 1.0);
    return t * t * (3.0 - 2.0 * t);
}

// The wake's foam in [0, 1] at off, a camera-relative (x, z) point in metres: the largest over
// the trail samples of a Kelvin ring's cusp (the ring of radius U·a/4 about P + d·U·a/4, bright
// at acos(1/3) from the travel direction, fading with age over the cusp life) and of the wash
// band along the segment to the next sample (its half-width grows with speed and age, fading
// over the wash life), ramped in from 0.3 to 2 m/s of speed, times the strength, over the samples
// uWakeFirst … uWakeEnd − 1 (a pass over a chunk of them: the max of the chunks' foam is the
// whole trail's). A point outside uWakeBounds, or no samples, returns 0 at once.
float WakeFoam(vec2 off) {
    if (uWakeCount <= 0 || any(lessThan(off, uWakeBounds.xy))
        || any(greaterThan(off, uWakeBounds.zw))) {
        return 0.0;
    }
    float foam = 0.0;
    for (int k = 0; k < WAKE_MAX; ++k) {
        int i = uWakeFirst + k;
        if (i >= uWakeEnd) break;
        vec4 s = uWakeSample[i];
        vec2 p = off - s.xy;
        float r = length(p);
        float a = max(s.z, 0.0);
        float speed = s.w;
        float radius = speed * a / 4.0;
        vec2 q = p - uWakeDir[i] * radius;   // from the ring's centre
        float rc = length(q);
        float width = max(uWakeShape.y, speed * uWakeShape.z / 4.0);
        float ring = exp(-((rc - radius) / width) * ((rc - radius) / width));
        float c = dot(q, uWakeDir[i]) / max(rc, 1e-6);
        // along the ring, the distance to its cusp point (acos(1/3) from the travel direction),
        // at least the spacing of successive cusps: a line, not a string of beads
        float arc = radius * abs(acos(clamp(c, -1.0, 1.0)) - 1.2309594);
        float reach = max(uWakeShape.y, 0.75 * speed * uWakeShape.z);
        float cusp = exp(-(arc / reach) * (arc / reach));
        float cuspFoam = ring * cusp * exp(-a / uWakeLife.x) * WakeSmooth(0.0, 1.0, radius);
        // the wash: a band along the path to the sample left before this one
        int j = min(i + 1, uWakeCount - 1);
        vec4 sj = uWakeSample[j];
        vec2 seg = sj.xy - s.xy;
        float f = clamp(dot(p, seg) / max(dot(seg, seg), 1e-12), 0.0, 1.0);
        float rw = length(p - f * seg);
        float aw = a + f * (max(sj.z, 0.0) - a);
        float uw = speed + f * (sj.w - speed);
        float half_ = 0.35 * uWakeShape.x + uWakeShape.w * uw * aw;
        float wash = 0.7 * exp(-(rw / half_) * (rw / half_)) * exp(-aw / uWakeLife.y);
        foam = max(foam, max(cuspFoam, wash) * WakeSmooth(0.3, 2.0, speed));
    }
    return clamp(foam * uWakeLife.z, 0.0, 1.0);
}
