#version 330 core
// The surfaces lab's opaque surface (spec/003 §2.5–2.8): the vertex stage. The meshes are in
// world space already (app.sim.surfaces_scene.mesh), so no model matrix; the fragment stage,
// surface.frag, documents the program's interface and equations.
// REFLECTION_OPTIMIZE (spec/003 §2.5, uReflectionOptimize): the reflection vector is computed
// here and interpolated, as the thesis's keyword does.
// Failure cases guarded: the normal and tangent are passed unnormalised and renormalised in the
// fragment stage; a vertex at the camera or a zero normal gives a zero reflection vector, which
// the fragment stage replaces by its own.

in vec3 in_position;
in vec3 in_normal;
in vec2 in_uv;
in vec4 in_tangent;

uniform mat4 uViewProj;
uniform mat4 uView;
uniform vec3 uCameraPos;
uniform bool uReflectionOptimize; // @param false §2.5 REFLECTION_OPTIMIZE: the reflection vector
                                  // per vertex, interpolated (cheaper; bends on coarse meshes)

out vec3 vWorldPos;
out vec3 vWorldNormal;
out vec4 vWorldTangent;
out vec2 vUV;
out float vViewDepth;   // distance along the camera's view axis (the cascades' split variable)
out vec3 vReflect;      // reflect(−v, n) at the vertex (used with uReflectionOptimize)

void main() {
    vWorldPos = in_position;
    vWorldNormal = in_normal;
    vWorldTangent = in_tangent;
    vUV = in_uv;
    vViewDepth = -(uView * vec4(in_position, 1.0)).z;
    vReflect = vec3(0.0);
    if (uReflectionOptimize) {
        vec3 v = uCameraPos - in_position;
        float lv = dot(v, v), ln = dot(in_normal, in_normal);
        if (lv > 1e-20 && ln > 1e-20) {
            vReflect = reflect(-v * inversesqrt(lv), in_normal * inversesqrt(ln));
        }
    }
    gl_Position = uViewProj * vec4(in_position, 1.0);
}
