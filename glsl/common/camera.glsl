// Camera rays for full-screen passes. Twin: Camera.ray_directions in app/sim/camera.py.
uniform vec3 uCameraPos;   // metres, world space (y up)
uniform vec3 uCamRight;
uniform vec3 uCamUp;
uniform vec3 uCamForward;
uniform float uTanHalfFov; // tan(vertical fov / 2)
uniform float uAspect;     // width / height

// uv in [0,1]^2, (0,0) at the bottom-left of the image.
vec3 CameraRayDirection(vec2 uv) {
    vec2 ndc = uv * 2.0 - 1.0;
    vec3 d = uCamForward + ndc.x * uTanHalfFov * uAspect * uCamRight + ndc.y * uTanHalfFov * uCamUp;
    return normalize(d);
}
