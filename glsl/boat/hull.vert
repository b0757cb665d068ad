#version 330 core
// The sailing boat's solid parts (spec/000 §1.3–1.4: the boat the buoyancy floats): hull, deck,
// mast and boom, in the boat frame (+x starboard, +y up, +z bow, y = 0 at the keel) placed in
// the world by the rigid body's pose.
// Equations: none (a rigid transform).
// Failure cases guarded: float32 precision far from the origin (the model matrix is built
// camera-relative on the CPU in float64, with the ocean's camera-relative view-projection, so the
// boat's depth and the water's agree exactly where they meet); normals are transformed by
// mat3(uModelRel), exact for the rotation and translation a rigid body has.
in vec3 in_position;
in vec3 in_normal;
in vec3 in_color;     // linear albedo: topsides, deck, spars (the bottom paint is by height)

uniform mat4 uModelRel;     // boat frame → world − camera
uniform mat4 uViewProjRel;  // the ocean's camera-relative view-projection

out vec3 vRel;        // world − camera
out vec3 vNormal;
out vec3 vColor;
out float vBoatY;     // height above the keel (boat frame)

void main() {
    vec4 rel = uModelRel * vec4(in_position, 1.0);
    vRel = rel.xyz;
    vNormal = mat3(uModelRel) * in_normal;
    vColor = in_color;
    vBoatY = in_position.y;
    gl_Position = uViewProjRel * rel;
}
