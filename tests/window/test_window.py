"""The desktop window under Xvfb: panel drawn by app/ui/imgui_renderer.py, fly keys, mouse look,
pause, screenshots that never overwrite, live shader edits with file:line errors."""

from __future__ import annotations

import json
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

from tests.helpers.window_driver import NO_XVFB, XVFB_SKIP, under_xvfb

DRIVER = Path(__file__).parent.parent / "helpers" / "window_driver.py"

pytestmark = [
    pytest.mark.window,
    pytest.mark.skipif(NO_XVFB, reason=XVFB_SKIP),
]


def _under_xvfb(args, cwd, timeout=120):
    return under_xvfb(args, cwd, timeout=timeout)


def test_window_driven_like_a_user(tmp_path):
    proc = _under_xvfb([sys.executable, str(DRIVER), str(tmp_path)], cwd=tmp_path)
    lines = [line for line in proc.stdout.splitlines() if line.startswith("RESULT ")]
    assert proc.returncode == 0 and lines, proc.stdout[-2000:] + proc.stderr[-2000:]
    r = json.loads(lines[-1][len("RESULT "):])
    assert r["panel_pixels"] > 2000  # the ImGui panel is drawn over the scene
    assert r["f1_hides_panel"]
    assert r["moved_forward_m"] == pytest.approx(30 / 60 * 5.0, rel=0.01)  # W: 5 m/s for 0.5 s
    assert r["yaw_change"] < -1.0  # dragging left turns left
    assert r["space_toggles_time"]
    assert r["bracket_hour_step"] == pytest.approx(0.25)
    assert len(r["screenshots"]) == 2 and len(set(r["screenshots"])) == 2
    assert "shots/sky-0001.png" not in r["screenshots"] and r["user_file_kept"]
    for shot in r["screenshots"]:
        assert (tmp_path / shot).stat().st_size > 1000
    assert r["edit_changed_image"] > 20 and r["edit_green_mean"] < 1.0  # the edit shows (red only)
    assert r["errors"] and all(e.startswith(r["expected_error_prefix"]) for e in r["errors"])
    assert r["still_rendering_after_typo"] < 0.5  # the last good program keeps rendering
    assert r["errors_after_fix"] == [] and r["restored_diff"] < 0.5
    assert r["new_param"]  # an annotated uniform became a parameter without Python changes
    assert r["escape_closes"]


@pytest.mark.parametrize("scene", ["probe", "materials", "planet", "noise", "clouds", "ocean"])
def test_natura_window_runs_frames_and_exits(tmp_path, scene):
    proc = _under_xvfb([sys.executable, "-m", "app.cli", "window", scene, "--frames", "10",
                        "--size", "320x180"], cwd=tmp_path)
    assert proc.returncode == 0, proc.stderr[-2000:]


def test_bake_progress_is_drawn_in_the_window(tmp_path):
    proc = _under_xvfb([sys.executable, str(DRIVER), str(tmp_path), "bake-progress"], cwd=tmp_path)
    lines = [line for line in proc.stdout.splitlines() if line.startswith("RESULT ")]
    assert proc.returncode == 0 and lines, proc.stdout[-2000:] + proc.stderr[-2000:]
    r = json.loads(lines[-1][len("RESULT "):])
    assert r["cache"] in ("miss", "rebuilt") and r["progress_frames"] >= 2


needs_xdotool = pytest.mark.skipif(shutil.which("xdotool") is None,
                                   reason="no xdotool to type real keys (apt-get install xdotool)")


def _result(proc) -> dict:
    lines = [line for line in proc.stdout.splitlines() if line.startswith("RESULT ")]
    assert proc.returncode == 0 and lines, proc.stdout[-2000:] + proc.stderr[-2000:]
    return json.loads(lines[-1][len("RESULT "):])


# the planet's keys (M, Up and the rest of its map): tests/window/test_window_keys.py


def test_the_sky_offers_its_keyframes_to_the_panel(tmp_path):
    r = _result(_under_xvfb([sys.executable, str(DRIVER), str(tmp_path), "sky-keyframes"],
                            cwd=tmp_path))
    assert "Sky keyframes (every 3 h)" in r["sky"]
    assert "Sky keyframes (every 3 h)" not in r["materials"]


@needs_xdotool
def test_ocean_models_switch_live_in_the_window(tmp_path):
    """Issue 6: sine → Gerstner → FFT chosen in the window each draw their own sea."""
    proc = _under_xvfb([sys.executable, str(DRIVER), str(tmp_path), "ocean-models"], cwd=tmp_path)
    lines = [line for line in proc.stdout.splitlines() if line.startswith("RESULT ")]
    assert proc.returncode == 0 and lines, proc.stdout[-2000:] + proc.stderr[-2000:]
    r = json.loads(lines[-1][len("RESULT "):])
    assert r["render_error"] == ""
    assert r["diff_sine_gerstner"] > 1.0 and r["diff_gerstner_fft"] > 1.0
    assert r["fft_sim"]


def test_the_fallback_font_is_matplotlibs_dejavu_found_without_importing_matplotlib():
    """The window's fallback font (the digests' maths signs) is matplotlib's DejaVu Sans, as
    matplotlib itself names it; looking it up no longer imports matplotlib, which cost every
    window's start about 0.1 s of CPU (`natura window sky` imports it nowhere else)."""
    import matplotlib

    probe = ("import sys; from app.ui.window import _fallback_font; print(_fallback_font()); "
             "print('matplotlib' in sys.modules)")
    proc = subprocess.run([sys.executable, "-c", probe], capture_output=True, text=True,
                          timeout=60)
    assert proc.returncode == 0, proc.stderr
    path, imported = proc.stdout.splitlines()
    assert Path(path) == Path(matplotlib.get_data_path()) / "fonts" / "ttf" / "DejaVuSans.ttf"
    assert imported == "False"
