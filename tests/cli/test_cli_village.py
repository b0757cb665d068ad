"""The village on the command line: ``--vr`` only where a scene has a VR mode (one line
otherwise), and a ``--camera`` given by the user is a free camera in a scene that places its
own (the village's third-person camera would otherwise move it)."""

from __future__ import annotations

from app.cli import _session_inputs, build_parser
from tests.helpers.cli import SMALL, run, usage_error


def _inputs(*argv: str):
    args = build_parser().parse_args(["render", *argv])
    return _session_inputs(args, args.scene)


def test_vr_switches_the_village_to_its_stereo_mode():
    params, _, _ = _inputs("village", "--vr")
    assert params["vr.enabled"] is True
    params, _, _ = _inputs("village")
    assert params["vr.enabled"] is False


def test_a_given_camera_is_a_free_camera_in_the_village():
    params, camera, _ = _inputs("village", "--camera", "1,30,40,10,-30")
    assert params["village.camera"] == "free"
    assert camera.position == (1.0, 30.0, 40.0) and camera.yaw == 10.0
    params, _, _ = _inputs("village", "--yaw", "30")
    assert params["village.camera"] == "third"  # a yaw alone turns the view, the hero follows


def test_vr_on_a_scene_without_it_is_one_line(tmp_path):
    r = run("render", "sky", "--vr", "--size", SMALL, "--out", "x.png", cwd=tmp_path)
    line = usage_error(r)
    assert line == "natura: --vr: scene 'sky' has no VR mode: allowed village"
    assert not (tmp_path / "x.png").exists()


def test_a_given_yaw_turns_the_hero(gl_ctx):
    from app.runtime import open_session

    params, camera, _ = _inputs("village", "--yaw", "90", "--set", "village.resolution=33",
                                "--set", "village.msaa=0")
    s = open_session("village", params, ctx=gl_ctx, camera=camera)
    try:
        s.scene.frame((32, 18))
        assert s.params["village.hero_heading"] == 90.0
        assert s.scene.camera.yaw == 90.0
    finally:
        s.release()
