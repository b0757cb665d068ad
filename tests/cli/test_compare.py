"""``natura compare`` as a user runs it (issue 17, deliverable 3): method 2 against Hillaire on
the planet writes the composite and its JSON with both timings and both errors; equal sides give
a black heat map; every bad set is one line (exit 2) before any render; nothing is overwritten
without --force. Plus the heat map's colours and gain, and the references kept equal to the
benches'. Sizes are tiny (llvmpipe on CI)."""

from __future__ import annotations

import json
import re

import numpy as np
import pytest
from PIL import Image

from app.cli import main
from app.teach import compare as cm

W, H = 96, 54
SIZE = f"{W}x{H}"


def natura(capsys, *args: str) -> tuple[int, str, str]:
    rc = main(list(args))
    out, err = capsys.readouterr()
    return rc, out, err


def one_line_error(rc: int, out: str, err: str) -> str:
    assert rc == 2, (rc, out, err)
    lines = err.strip().splitlines()
    assert len(lines) == 1 and "Traceback" not in err, err
    assert out == ""
    return lines[0]


def test_planet_method_2_against_hillaire(tmp_path, capsys, monkeypatch):
    """The issue's example: both images, both timings, the difference and both errors."""
    monkeypatch.chdir(tmp_path)
    rc, out, err = natura(capsys, "compare", "planet", "--a", "planet.method=lut",
                          "--b", "planet.method=hillaire", "--size", SIZE, "--rounds", "2",
                          "--out", "cmp.png")
    assert rc == 0, err
    lines = out.splitlines()
    assert lines[-2:] == ["cmp.png", "cmp.json"]
    caption = lines[:-2]
    text = "\n".join(caption)
    assert "A: planet.method=lut" in text and "B: planet.method=hillaire" in text
    assert re.search(r"A [\d.]+ ms \[[\d.]+–[\d.]+\] · B [\d.]+ ms \[[\d.]+–[\d.]+\] · "
                     r"B/A [\d.]+×", text), text
    assert "error vs reference" in text and "gain ×" in text and "renderer: " in text
    assert caption[-1].startswith("natura compare planet --size 96x54 --a planet.method=lut")

    fig = json.loads((tmp_path / "cmp.json").read_text(encoding="utf-8"))
    assert fig["caption"] == caption and fig["rounds"] == 2 and fig["size"] == [W, H]
    for side in (fig["a"], fig["b"]):
        assert 0 < side["ms_p25"] <= side["ms"] <= side["ms_p75"]
    # both errors against the single-scattering reference: the LUT method is close to it,
    # Hillaire's multiple scattering adds light the reference does not have
    assert 0.0 < fig["a"]["error"] < 0.1
    assert fig["b"]["error"] > 2 * fig["a"]["error"]
    d = fig["difference"]
    assert d["mean_abs"] > 0 and d["gain"] == pytest.approx(1.0 / d["scale"])

    with Image.open(tmp_path / "cmp.png") as im:
        assert im.mode == "RGB"
        pixels = np.asarray(im)
    assert pixels.shape[1] == 3 * W and pixels.shape[0] > H  # A | B | heat, caption below
    assert fig["image_size"] == [pixels.shape[1], pixels.shape[0]]
    heat = pixels[20:H, 2 * W:].astype(int)  # below the panel's label
    assert heat.max() > 100  # differences shown, magnified
    assert sorted(p.name for p in tmp_path.iterdir()) == ["cmp.json", "cmp.png"]


def test_equal_sides_have_a_black_heat_map_and_force_overwrites(tmp_path, capsys,
                                                                monkeypatch):
    monkeypatch.chdir(tmp_path)
    (tmp_path / "cmp.png").write_bytes(b"old")
    (tmp_path / "cmp.json").write_text("old")
    rc, out, err = natura(capsys, "compare", "sky", "--a", "sky.sun_size=0.1",
                          "--b", "sky.sun_size=0.1", "--size", SIZE, "--rounds", "1",
                          "--layout", "wipe", "--wipe", "0.3", "--out", "cmp.png", "--force")
    assert rc == 0, err
    assert "difference B − A: none (the images are identical)" in out
    assert "no reference for the scene 'sky'" in out
    fig = json.loads((tmp_path / "cmp.json").read_text(encoding="utf-8"))
    assert fig["difference"]["max_abs"] == 0.0 and fig["a"]["error"] is None
    assert fig["layout"] == "wipe" and fig["wipe"] == 0.3
    with Image.open(tmp_path / "cmp.png") as im:
        pixels = np.asarray(im)
    assert pixels.shape[1] == 2 * W  # the wipe, then the heat map
    assert pixels[20:H, W:].max() == 0  # black: no difference (below the label)
    wiped = pixels[20:H, :W].astype(int)
    col = round(0.3 * W) - 1
    assert (wiped[:, col] == 255).all()  # the wipe's line


@pytest.mark.parametrize("args, culprit", [
    (("--a", "nosuch=1"), "'nosuch=1'"),
    (("--b", "sky.sun_size"), "'sky.sun_size' is not NAME=VALUE"),
    (("--a", "sky.sun_size=0.1", "--b", "sky.sun_size=7"), "'sky.sun_size=7'"),
    ((), "nothing differs"),
    (("--b", "sky.sun_size=0.1", "--wipe", "0.3"), "--layout wipe"),
    (("--b", "sky.sun_size=0.1", "--rounds", "0"), "--rounds 0"),
])
def test_bad_input_is_one_line_before_any_render(tmp_path, capsys, monkeypatch, args,
                                                 culprit):
    monkeypatch.chdir(tmp_path)
    line = one_line_error(*natura(capsys, "compare", "sky", "--size", SIZE, *args,
                                  "--out", "cmp.png"))
    assert culprit in line and "allowed" in line
    assert list(tmp_path.iterdir()) == []


@pytest.mark.parametrize("existing", ["cmp.png", "cmp.json"])
def test_nothing_is_overwritten_without_force(tmp_path, capsys, monkeypatch, existing):
    monkeypatch.chdir(tmp_path)
    (tmp_path / existing).write_bytes(b"mine")
    line = one_line_error(*natura(capsys, "compare", "sky", "--b", "sky.sun_size=0.1",
                                  "--size", SIZE, "--out", "cmp.png"))
    assert f"refusing to overwrite '{existing}'" in line
    assert [p.name for p in tmp_path.iterdir()] == [existing]
    assert (tmp_path / existing).read_bytes() == b"mine"


def test_heat_map_colours_and_gain():
    diff = np.array([[1.0, -1.0, 0.0, 0.25]])
    heat = cm.heat_map(diff, 1.0).astype(int)
    assert heat[0, 0, 0] > 200 and heat[0, 0, 2] < heat[0, 0, 0] / 2  # B brighter: red
    assert heat[0, 1, 2] > 200 and heat[0, 1, 0] < heat[0, 1, 2] / 2  # B darker: blue
    assert (heat[0, 2] == 0).all()  # equal: black
    assert 0 < heat[0, 3, 0] < heat[0, 0, 0]
    ramp = np.linspace(0.0, 1.0, 1001)
    gain, scale = cm.choose_gain(ramp)
    assert scale == pytest.approx(0.99) and gain == pytest.approx(1 / 0.99)
    sparse = np.zeros(1000)
    sparse[3] = -0.5  # fewer than 1 % of the pixels differ: the largest maps to full scale
    assert cm.choose_gain(sparse) == (2.0, 0.5)
    assert cm.choose_gain(np.zeros(10)) == (1.0, 0.0)


def test_references_are_the_benches():
    from app.bench.clouds import REFERENCE as clouds_reference
    from app.bench.surfaces_transparency import REFERENCE as surfaces_reference

    assert cm.CLOUDS_REFERENCE == clouds_reference
    assert cm.SURFACES_REFERENCE == surfaces_reference
    assert cm.reference_of("sky") is None and cm.reference_of("planet") is not None


def test_materials_reference_judges_the_ring_filter_and_not_the_noises(tmp_path, capsys,
                                                                       monkeypatch):
    """Issue 38: the materials handout's errors measured aliasing. The reference (hard edges
    supersampled 8 × 8) judges the ring filter: filtered edges come nearer to it than hard
    ones; two noises get no error figure rather than one that is mostly their shared aliasing."""
    monkeypatch.chdir(tmp_path)
    rc, out, err = natura(capsys, "compare", "materials", "--a", "materials.filter_rings=false",
                          "--b", "materials.filter_rings=true", "--size", SIZE, "--rounds", "1",
                          "--out", "rings.png")
    assert rc == 0, err
    fig = json.loads((tmp_path / "rings.json").read_text(encoding="utf-8"))
    assert 0.0 < fig["b"]["error"] < fig["a"]["error"]
    rc, out, err = natura(capsys, "compare", "materials", "--a", "materials.noise=value",
                          "--b", "materials.noise=gradient", "--size", SIZE, "--rounds", "1",
                          "--out", "noise.png")
    assert rc == 0, err
    fig = json.loads((tmp_path / "noise.json").read_text(encoding="utf-8"))
    assert fig["a"]["error"] is None and fig["b"]["error"] is None
    assert "error: none — no reference for materials.noise" in out
