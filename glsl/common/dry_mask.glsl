// Keeps the sea out of a hull (spec/000 §4 item 8: waves drawn through the boat in rough seas).
// A floating object publishes the window depths of its dry volume — the hull closed by its deck
// raised by a bulwark — front faces (nearest) and back faces (farthest); a water fragment
// between the two lies inside the boat and is discarded. Water in front of the boat (a crest
// between it and the camera) is nearer than the front faces and stays: unlike a plain stencil,
// the boat is not drawn over every wave. Failure cases guarded: a camera inside the volume sees
// no front face (depth 1), so nothing is masked rather than everything; without a mask
// (uDryMask = 0) nothing is read.
uniform int uDryMask;            // 1: the textures below hold a dry volume
uniform sampler2D uDryFront;     // window depth of the nearest front face (1: none)
uniform sampler2D uDryBack;      // window depth of the farthest back face (0: none)

bool InsideDryVolume() {
    if (uDryMask == 0) return false;
    ivec2 px = ivec2(gl_FragCoord.xy);
    float front = texelFetch(uDryFront, px, 0).r;
    float back = texelFetch(uDryBack, px, 0).r;
    return gl_FragCoord.z > front && gl_FragCoord.z < back;
}
