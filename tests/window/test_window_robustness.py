"""What must not take the window down (issue list of the window hardening): screenshot, preset
and keyframe folders that are files or take no files, a file name taken between the check and
the link, a shader typo (printed whole to the terminal once, wrapped in the panel), a shader
library or a scene that raises. Each is a one-line message in the panel and on stderr, and the
window keeps drawing frames. Screenshots are asked for with the real P / F12 keys."""

from __future__ import annotations

import shutil

import pytest

from tests.helpers.window_driver import NO_XVFB, XDOTOOL_SKIP, XVFB_SKIP, drive

pytestmark = [
    pytest.mark.window,
    pytest.mark.skipif(NO_XVFB, reason=XVFB_SKIP),
    pytest.mark.skipif(shutil.which("xdotool") is None, reason=XDOTOOL_SKIP),
]


@pytest.fixture(scope="module")
def run(tmp_path_factory):
    work = tmp_path_factory.mktemp("robustness")
    r, proc = drive("robustness", work)
    return r, proc, work


CASES = {  # outcome → what its one-line message must say
    "shot_folder_is_file": "screenshot not saved: screenshots is a file, not a folder",
    "shot_folder_cannot_be_made": "screenshot not saved: cannot make the folder /sys/natura-shots",
    "shot_folder_read_only": "screenshot not saved in /sys",
    "preset_folder_is_file": "preset not saved: presets is a file, not a folder",
    "preset_folder_read_only": "preset not saved in /sys",
    "keyframes_read_only": "keyframes not saved in /sys",
}


@pytest.mark.parametrize("case", sorted(CASES))
def test_unwritable_folders_are_a_message_not_a_crash(run, case):
    r, proc, _ = run
    o = r[case]
    assert o["made"] == [] and not o["closing"] and o["frames_after"], o
    (message,) = o["messages"]
    assert message.startswith(CASES[case]) and "\n" not in message, message
    assert f"natura: {message}\n" in proc.stderr  # and on the terminal


def test_files_in_the_way_are_left_alone_and_good_folders_still_work(run):
    r, _, work = run
    assert r["shot_file_kept"] and r["preset_file_kept"]
    assert r["preset_saved"]["made"] == ["my-presets/sky-0001.toml"]
    assert "scene sky" in (work / "my-presets" / "sky-0001.toml").read_text()
    assert r["keyframes_saved"]["made"] == ["keyframes-0001.toml"]
    assert (work / "keyframes-0001.toml").stat().st_size > 100


def test_a_screenshot_name_taken_in_a_race_takes_the_next_number(run):
    """next_free_path returned a name another process had just taken: the writer's
    OutputExistsError makes the window try the next number, not give up."""
    r, _, work = run
    race = r["race"]
    assert race["calls"] == 2 and race["taken_kept"]
    assert race["screenshots"] == ["shots/sky-0002.png"]
    assert (work / "shots" / "sky-0002.png").stat().st_size > 1000
    assert race["messages"] == ["saved shots/sky-0002.png"]


def test_a_shader_error_is_printed_once_and_wrapped_in_the_panel(run):
    r, proc, _ = run
    s = r["shader"]
    assert s["errors"] and s["errors_after_fix"] == []
    long = [e for e in s["errors"] if "an_undeclared_name_long_enough_to_wrap" in e]
    assert long
    for error in s["errors"]:
        # three polls with the error standing: printed whole exactly once
        assert proc.stderr.count(f"natura: shader error: {error}\n") == 1, proc.stderr[-3000:]
    assert s["wrap_pushed"] > 0
    drawn = {d["text"]: d for d in s["drawn"]}
    assert set(drawn) == set(s["errors"])  # every error drawn, whole
    for d in drawn.values():
        assert d["width"] <= d["window_width"], d  # not cut off at the panel's edge
    d = drawn[long[0]]
    assert d["height"] >= 1.9 * d["line_height"], d  # it wrapped onto a second line


def test_a_raising_shader_library_or_scene_keeps_the_window_running(run):
    r, proc, _ = run
    p = r["poll_error"]
    assert p["error"] == "shader reload failed: the shader library broke"
    assert not p["closing"] and p["messages"] == [p["error"]] and p["after"] is None
    assert proc.stderr.count(f"natura: {p['error']}\n") == 1  # two polls, printed once
    e = r["render_error"]
    assert e["error"] == "render failed: the scene broke" and not e["closing"]
    assert e["after"] is None
    assert proc.stderr.count("natura: render failed: the scene broke\n") == 1  # 3 frames, once
    assert r["escape_closes"]
