#version 330 core
// World-space markers above the characters (spec/003 §2.15: the thesis moves the NPCs' UI
// from head-locked panels to world-space canvases above them, because head-locked panels cause
// discomfort in VR). A billboard per character: its centre above the head, its corners along
// the camera's right and up vectors (both eyes of a stereo pair share the head's orientation,
// so they see one quad and fuse it at its depth). No equation of the thesis: a camera-facing
// quad. Twin: billboard_corners in app/sim/vr.py.
// Failure cases guarded: positions are camera-relative (world − camera) before the
// view-projection, so float32 stays exact far from the origin; the quad never turns edge-on
// (it is parallel to the image plane whatever the camera's pitch).

in vec3 in_centre;     // the marker's centre, world [m]
in vec2 in_corner;     // (±½, ±½)
in float in_icon;      // which icon: the index in app.sim.vr.ICON_ROLES

uniform mat4 uViewProj;   // view-projection for camera-relative positions
uniform vec3 uCameraPos;
uniform vec3 uCamRight;
uniform vec3 uCamUp;
uniform float uMarkerSize;  // the icon's side [m]

out vec2 vUV;
flat out float vIcon;

void main() {
    vec3 world = in_centre + uMarkerSize * (in_corner.x * uCamRight + in_corner.y * uCamUp);
    vUV = in_corner + 0.5;
    vIcon = in_icon;
    gl_Position = uViewProj * vec4(world - uCameraPos, 1.0);
}
