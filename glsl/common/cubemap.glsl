// Direction of a cubemap texel, OpenGL face order +X, -X, +Y, -Y, +Z, -Z (GL spec table 8.19).
// st in [-1, 1]^2 is the face coordinate with t growing downward in the stored image.
// Twin: cubemap_face_direction in app/sim/sky.py.
vec3 CubemapFaceDirection(int face, vec2 st) {
    float s = st.x, t = st.y;
    vec3 d;
    if (face == 0)      d = vec3( 1.0,  -t,  -s);
    else if (face == 1) d = vec3(-1.0,  -t,   s);
    else if (face == 2) d = vec3(   s, 1.0,   t);
    else if (face == 3) d = vec3(   s,-1.0,  -t);
    else if (face == 4) d = vec3(   s,  -t, 1.0);
    else                d = vec3(  -s,  -t,-1.0);
    return normalize(d);
}
