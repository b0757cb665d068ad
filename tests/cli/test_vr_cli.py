"""``natura render village --vr`` as a user types it (spec/003 §2.15, criteria 35–36): it writes
a side-by-side pair whose halves differ and which carries the health ring at (ScreenX, ScreenY)
of each half; bad VR inputs are refused in one line. Small renders (96×54): CI has two cores."""

from __future__ import annotations

import numpy as np
from PIL import Image

from tests.helpers import measures
from tests.helpers.cli import run, usage_error

SIZE = (96, 54)
#: a head before Lord Barus's hall (near geometry: the halves differ by more than the sky)
CAMERA = "0,3.2,-11,0,-5,60"
RING = ["--set", "vr.lives=8", "--set", "vr.remaining=3", "--set", "vr.visibility=1",
        "--set", "vr.element_size=0.04"]


def _render(tmp_path, name, *args):
    r = run("render", "village", "--vr", "--size", f"{SIZE[0]}x{SIZE[1]}", "--camera", CAMERA,
            *RING, *args, "--out", name, cwd=tmp_path)
    assert r.returncode == 0, r.stderr
    assert r.stdout.strip() == name
    with Image.open(tmp_path / name) as im:
        assert im.size == SIZE and im.format == "PNG"
        return np.asarray(im.convert("RGB"), np.float64) / 255.0


def test_render_village_vr_writes_a_pair_whose_halves_differ_with_the_ring(tmp_path):
    pair = _render(tmp_path, "v.png")
    left, right = pair[:, :48], pair[:, 48:]
    assert np.abs(left - right).mean() > 2 / 255
    bare = _render(tmp_path, "bare.png", "--set", "vr.health_ring=off")
    diff = np.abs(pair - bare).max(-1)
    for x0 in (0, 48):  # the ring at (ScreenX, ScreenY) of each eye's 48 × 54 image
        band = diff[:, x0:x0 + 48] > 0.03  # where the ring covers (full or empty sections)
        assert band.sum() > 40
        cx, cy = measures.ring_centroid(band.astype(float))
        assert abs(cx - 0.666 * 48) <= 1.0 and abs(cy - 0.579 * 54) <= 1.0, (x0, cx, cy)


def test_bad_vr_inputs_are_one_line_errors(tmp_path):
    line = usage_error(run("render", "village", "--vr", "--set", "vr.ipd=-0.1", "--out",
                           "x.png", cwd=tmp_path))
    assert "vr.ipd" in line and "allowed a number in [0, 0.2]" in line
    line = usage_error(run("render", "village", "--set", "vr.lives=0", "--out", "x.png",
                           cwd=tmp_path))
    assert "vr.lives" in line and "allowed an integer in [1, 64]" in line
    line = usage_error(run("render", "sky", "--vr", "--out", "x.png", cwd=tmp_path))
    assert "--vr" in line and "village" in line
    assert not list(tmp_path.iterdir())
