#version 330 core
// The sailing boat's solid parts (spec/000 §1.3–1.4: the boat the buoyancy floats): the hull,
// its deck fittings (cabin, cockpit, toe rails: app/effects/boat/details.py), mast and boom, in
// the boat frame (+x starboard, +y up, +z bow, y = 0 at the keel) placed in the world by the
// rigid body's pose.
// Equations: none (a rigid transform).
// Failure cases guarded: float32 precision far from the origin (the model matrix is built
// camera-relative on the CPU in float64, with the ocean's camera-relative view-projection, so the
// boat's depth and the water's agree exactly where they meet); normals are transformed by
// mat3(uModelRel), exact for the rotation and translation a rigid body has.
in vec3 in_position;
in vec3 in_normal;
in vec3 in_color;     // linear albedo (the hull's paint stripes are by height, in the fragment)
in vec3 in_extra;     // (depth below the sheer [m] or −1, material code, ambient occlusion)

uniform mat4 uModelRel;     // boat frame → world − camera
uniform mat4 uViewProjRel;  // the ocean's camera-relative view-projection

out vec3 vRel;        // world − camera
out vec3 vNormal;
out vec3 vColor;
out vec3 vBoatPos;    // boat frame (the part's own frame for the boom)
out vec3 vExtra;

void main() {
    vec4 rel = uModelRel * vec4(in_position, 1.0);
    vRel = rel.xyz;
    vNormal = mat3(uModelRel) * in_normal;
    vColor = in_color;
    vBoatPos = in_position;
    vExtra = in_extra;
    gl_Position = uViewProjRel * rel;
}
