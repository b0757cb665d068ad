"""The inputs a fuzz run of the command line found after the fuzz suite passed (issue 36), each
fed as it was found: a frame size the renderer cannot hold, output that cannot carry Unicode, a
disk that fills up in the middle of ``--frames``, a camera far outside the world, messages that
showed Python reprs or were cut short, an output path ending in a slash, and values inside
their ranges that a rule between parameters refuses. Every answer is one ``natura:`` line, the
exit code of its kind, and nothing left behind.
"""

from __future__ import annotations

import contextlib
import json
import os
import resource
import subprocess
from pathlib import Path

import pytest

from app import PROJECT_ROOT
from app.errors import quote_path
from app.gpu.targets import TargetSizeError, check_frame_size
from tests.cli.fuzz_cases import is_root
from tests.helpers.cli import SMALL, messages, run, usage_error


def leftovers(folder: Path) -> list[str]:
    return sorted(p.name for p in folder.iterdir())


# ---- a frame size the renderer cannot hold ------------------------------------------------------

@pytest.mark.slow  # the probe allocates (and clears) a few GiB on a software renderer
def test_the_largest_documented_size_is_refused_before_any_work_when_it_cannot_be_held(
        tmp_path, gl_ctx):
    from app.gpu.targets import _holds

    if _holds(gl_ctx, (16384, 16384)):
        pytest.skip("this renderer holds a 16384x16384 float target: nothing to refuse")
    r = run("render", "sky", "--size", "16384x16384", "--out", "big.png", cwd=tmp_path)
    line = usage_error(r)
    assert line.startswith("natura: --size 16384x16384 needs a 4.0 GiB float colour target")
    assert "allowed up to about " in line, line
    assert "internal error" not in r.stderr and leftovers(tmp_path) == []
    # the size it names is one the renderer holds
    w, h = (int(v) for v in line.rsplit("about ", 1)[1].split()[0].split("x"))
    assert w == h and 4096 <= w < 16384 and _holds(gl_ctx, (w, h))


class _Limits:
    """A context as check_frame_size reads it: only its limits."""

    def __init__(self, texture: int, renderbuffer: int, viewport: tuple[int, int]):
        self.info = {"GL_MAX_TEXTURE_SIZE": texture, "GL_MAX_RENDERBUFFER_SIZE": renderbuffer,
                     "GL_MAX_VIEWPORT_DIMS": viewport, "GL_RENDERER": "a small GPU"}


@pytest.mark.parametrize("limits, size", [
    ((4096, 8192, (8192, 8192)), (4097, 16)),
    ((8192, 2048, (8192, 8192)), (16, 2049)),
    ((8192, 8192, (3000, 3000)), (3001, 3001)),
], ids=["texture", "renderbuffer", "viewport"])
def test_a_side_over_any_of_the_contexts_limits_is_refused_with_that_limit(limits, size):
    ctx = _Limits(*limits)
    limit = min(limits[0], limits[1], min(limits[2]))
    with pytest.raises(TargetSizeError, match=rf"allowed 1\.\.{limit}$"):
        check_frame_size(ctx, size)  # type: ignore[arg-type]


def test_the_size_option_documents_the_renderers_limit():
    from app.cli import build_parser

    help_text = " ".join(build_parser()._subparsers._group_actions[0]  # type: ignore[union-attr]
                         .choices["render"].format_help().split())
    assert "1..16384 a side, within what the renderer can allocate" in help_text


# ---- output that cannot carry Unicode -----------------------------------------------------------

@pytest.mark.parametrize("args", [["scenes"], ["params", "sky"]], ids=["scenes", "params"])
def test_an_ascii_only_output_gets_every_line(tmp_path, args):
    env = dict(os.environ, PYTHONIOENCODING="ascii")
    r = run(*args, cwd=tmp_path, env=env)
    assert r.returncode == 0 and r.stderr == "", r.stderr
    assert r.stdout.isascii() and "\\xa7" in r.stdout  # the § of a thesis section, escaped
    assert len(r.stdout.splitlines()) > 20


def test_an_image_with_a_unicode_name_is_written_and_named_on_an_ascii_output(tmp_path):
    env = dict(os.environ, PYTHONIOENCODING="ascii")
    r = run("render", "sky", "--size", SMALL, "--out", "ünï.png", cwd=tmp_path, env=env)
    assert r.returncode == 0, r.stderr
    assert leftovers(tmp_path) == ["ünï.png"]
    assert r.stdout.strip() == "\\xfcn\\xef.png"


# ---- a disk that fills up during --frames -------------------------------------------------------

@contextlib.contextmanager
def tiny_tmpfs(path: Path):
    """A 64 KB tmpfs at ``path`` (root only), unmounted afterwards."""
    path.mkdir()
    r = subprocess.run(["mount", "-t", "tmpfs", "-o", "size=64k", "tmpfs", str(path)],
                       capture_output=True, text=True)
    if r.returncode != 0:
        pytest.skip(f"cannot mount a 64 KB tmpfs here ({r.stderr.strip() or 'mount failed'})")
    try:
        yield path
    finally:
        subprocess.run(["umount", "-l", str(path)], capture_output=True)


def _full_disk_run(tmp_path: Path, how: str, *args: str) -> tuple[subprocess.CompletedProcess,
                                                                  Path]:
    if how == "tmpfs":
        if not is_root():
            pytest.skip("mounting a 64 KB tmpfs needs root")
        with tiny_tmpfs(tmp_path / "F") as folder:
            r = run(*args[:-1], "--out", str(folder / args[-1]), cwd=tmp_path)
            names = leftovers(folder)
        return r, Path(json.dumps(names))
    # a file-size limit on the process: a write past 64 KB fails (EFBIG) as on a full disk
    folder = tmp_path / "F"
    folder.mkdir()

    def limit():
        resource.setrlimit(resource.RLIMIT_FSIZE, (64 * 1024, resource.RLIM_INFINITY))

    from tests.helpers.cli import NATURA

    env = dict(os.environ)
    env["PYTHONPATH"] = str(PROJECT_ROOT)
    r = subprocess.run([*NATURA, *args[:-1], "--out", str(folder / args[-1])], cwd=tmp_path,
                       env=env, capture_output=True, text=True, timeout=120, preexec_fn=limit)
    return r, Path(json.dumps(leftovers(folder)))


def _check_frames_answer(r: subprocess.CompletedProcess, kept: list[str]) -> None:
    assert r.returncode == 2, r.stderr
    lines = [line for line in messages(r.stderr.replace("\r", "\n"))
             if not line.startswith("rendering [")]  # the progress line, redrawn in place
    assert len(lines) == 1, r.stderr
    line = lines[0]
    n = len(kept)
    assert 1 <= n < 5 and kept == [f"seq-{i:04d}.png" for i in range(1, n + 1)], kept
    assert line.startswith(f"natura: cannot write frame {n + 1} '") and \
        f"/seq-{n + 1:04d}.png' (No space left on device): allowed a folder on a disk with free " \
        f"space; {f'frames 1–{n} are' if n > 1 else 'frame 1 is'} kept (named on stdout)" in line
    assert len(line) <= 200 and "nothing was left behind" not in line, line
    # the kept frames are named on stdout, one per line
    assert [Path(p).name for p in r.stdout.split()] == kept


def test_a_disk_filling_up_during_frames_names_the_frames_it_kept(tmp_path):
    r, names = _full_disk_run(tmp_path, "tmpfs", "render", "sky", "--size", "200x200",
                              "--frames", "5", "seq.png")
    _check_frames_answer(r, json.loads(str(names)))


def test_a_disk_full_at_the_third_frame_keeps_two(tmp_path, monkeypatch, capsys):
    """The same, where no tmpfs can be mounted: the third frame's write fails as a full disk
    makes it fail (in this process, the command line's own main)."""
    import errno

    from app import cli, imageio

    real = imageio.write_png
    calls = []

    def fill_up(path, *args, **kw):
        calls.append(path)
        if len(calls) == 3:
            with imageio.writing(Path(path)):
                raise OSError(errno.ENOSPC, "No space left on device")
        return real(path, *args, **kw)

    monkeypatch.setattr(imageio, "write_png", fill_up)
    monkeypatch.chdir(tmp_path)
    (tmp_path / "F").mkdir()
    code = cli.main(["render", "sky", "--size", SMALL, "--frames", "5", "--out", "F/seq.png"])
    out, err = capsys.readouterr()
    _check_frames_answer(subprocess.CompletedProcess([], code, out, err),
                         leftovers(tmp_path / "F"))


@pytest.mark.parametrize("how", ["tmpfs", "file size limit"])
def test_a_full_disk_exr_message_names_the_whole_file_and_the_reason(tmp_path, how):
    r, names = _full_disk_run(tmp_path, how, "render", "sky", "--size", "200x200",
                              "a-long-name-for-an-image-of-the-evening-sky.exr")
    assert r.returncode == 2, r.stderr
    line = messages(r.stderr)[-1]
    assert "/a-long-name-for-an-image-of-the-evening-sky.exr' (" in line, line
    assert ("No space left on device" if how == "tmpfs" else "File too large") in line, line
    assert "nothing was left behind" in line and json.loads(str(names)) == []
    assert "RuntimeError" not in line and ".natura-" not in line


# ---- a camera far outside the world -------------------------------------------------------------

@pytest.mark.parametrize("scene, camera, allowed", [
    ("planet", "1e308,0,0", "allowed at most 5e+07 m from it"),
    ("ocean", "1e30,0,0", "allowed x in [-2e+07, 2e+07] m"),
])
def test_a_camera_far_outside_the_world_is_refused_with_the_scenes_range(tmp_path, scene,
                                                                        camera, allowed):
    r = run("render", scene, "--camera", camera, "--size", SMALL, "--out", "far.png",
            cwd=tmp_path)
    line = usage_error(r)
    assert line.startswith("natura: --camera") and line.endswith(allowed), line
    assert "Warning" not in r.stderr and leftovers(tmp_path) == []


def test_a_camera_within_a_scenes_range_still_renders(tmp_path):
    r = run("render", "planet", "--camera", "0,400000,0,0,-60", "--size", SMALL, "--out",
            "space.png", cwd=tmp_path)
    assert r.returncode == 0 and "Warning" not in r.stderr, r.stderr


# ---- messages in words, whole -------------------------------------------------------------------

def test_a_zero_vector_is_shown_as_typed_and_refused_before_any_work(tmp_path):
    line = usage_error(run("render", "sky", "--set", "sky.ecliptic=0,0,0", "--size", SMALL,
                           cwd=tmp_path))
    assert line == "natura: sky.ecliptic=0.0,0.0,0.0: allowed sky.ecliptic not the zero axis"


def test_a_preset_date_is_shown_as_written(tmp_path):
    (tmp_path / "dt.toml").write_text("[sky]\nsun_size = 1979-05-27T07:32:00\n")
    line = usage_error(run("render", "sky", "--preset", "dt.toml", "--size", SMALL,
                           cwd=tmp_path))
    assert "sky.sun_size=1979-05-27T07:32:00 is not a number" in line
    assert "datetime" not in line


def test_a_sweeps_file_with_a_bad_value_is_refused_in_words(tmp_path):
    report = json.loads((PROJECT_ROOT / "docs" / "bench-planet.json").read_text())
    report["sweep"]["accuracy"]["rows"][0]["value"] = "abc"
    (tmp_path / "bad.json").write_text(json.dumps(report))
    r = run("render", "planet", "--quality", "auto", "--error-budget", "0.01", "--sweeps",
            "bad.json", "--size", SMALL, "--out", "q.png", cwd=tmp_path)
    line = usage_error(r)
    assert line == ("natura: --sweeps 'bad.json': its sweeps are not laid out as natura bench "
                    "planet writes them (the value 'abc' is not an integer): allowed a report "
                    "of natura bench planet (JSON, with its sweeps)")
    assert leftovers(tmp_path) == ["bad.json"]


@pytest.mark.skipif(not Path("/dev/full").exists(), reason="no /dev/full on this system")
@pytest.mark.parametrize("args", [["scenes"], ["params", "sky"], ["--help"]])
def test_a_full_standard_output_is_named(tmp_path, args):
    with open("/dev/full", "w") as full:
        from tests.helpers.cli import NATURA

        env = dict(os.environ, PYTHONPATH=str(PROJECT_ROOT))
        r = subprocess.run([*NATURA, *args], cwd=tmp_path, env=env, stdout=full,
                           stderr=subprocess.PIPE, text=True, timeout=60)
    assert r.returncode == 2
    assert r.stderr == ("natura: cannot write to standard output (No space left on device, "
                        "errno 28): allowed an output with room for it (a terminal, a pipe, a "
                        "file on a disk with free space)\n")


#: the noise lab with its smallest bakes: it bakes (and stores) three textures in a moment
SMALL_BAKES = ("render", "noise", "--size", "16x16", "--out", "c.png",
               "--set", "bake_shape.size=8", "--set", "bake_detail.size=8",
               "--set", "bake_weather.size=8")


def _cache_lines(r: subprocess.CompletedProcess) -> list[str]:
    assert r.returncode == 0, r.stderr
    lines = messages(r.stderr)
    assert "Warning" not in r.stderr and "app/" not in r.stderr, r.stderr
    return lines


def test_a_bake_cache_path_that_is_a_file_is_one_line(tmp_path):
    (tmp_path / "cachefile").write_text("")
    env = dict(os.environ, NATURA_CACHE=str(tmp_path / "cachefile"))
    r = run(*SMALL_BAKES, cwd=tmp_path, env=env)
    assert _cache_lines(r) == [
        f"natura: bake cache {quote_path(tmp_path / 'cachefile')} is a file, not a folder: "
        "baking without the cache (allowed $NATURA_CACHE or ~/.cache naming a folder you can "
        "write)"]


def test_a_home_whose_cache_cannot_be_made_is_one_line(tmp_path):
    home = tmp_path / "home"
    home.mkdir()
    if is_root():  # root writes anywhere: a file where ~/.cache should be stands in
        (home / ".cache").write_text("")
    else:
        home.chmod(0o555)
    env = {k: v for k, v in os.environ.items() if k not in ("NATURA_CACHE", "XDG_CACHE_HOME")}
    env["HOME"] = str(home)
    try:
        r = run(*SMALL_BAKES, cwd=tmp_path, env=env)
    finally:
        home.chmod(0o755)
    lines = _cache_lines(r)
    assert len(lines) == 1 and lines[0].startswith("natura: bake cache "), lines
    assert lines[0].endswith("baking without the cache (allowed $NATURA_CACHE or ~/.cache "
                             "naming a folder you can write)")


def test_an_output_path_ending_in_a_slash_is_refused(tmp_path):
    line = usage_error(run("render", "sky", "--size", SMALL, "--out", "x.png/", cwd=tmp_path))
    assert line == ("natura: output 'x.png/' ends in a folder separator (a folder's path): "
                    "allowed a file name ending in .png, .exr")
    assert leftovers(tmp_path) == []


# ---- rules between parameters -------------------------------------------------------------------

JOINT_CASES = [
    ("clouds", "bake_shape.cells_g=8", "bake_shape.cells_g < cells_b < cells_a"),
    ("noise", "bake_shape.cells_a=8", "bake_shape.cells_g < cells_b < cells_a"),
    ("clouds", "bake_detail.cells_r=4", "bake_detail.cells_r < cells_g < cells_b"),
    ("clouds", "clouds.base_height=5000", "clouds.max_height ≥ base_height + 1 m"),
    ("clouds", "clouds.max_height=1000", "clouds.max_height ≥ base_height + 1 m"),
    ("ocean", "ocean.patch_sizes=5,17,250,1", "falling patch sizes that hold their bands"),
    ("maritime", "ocean.patch_sizes=250,250,5,1", "falling patch sizes that hold their bands"),
]


@pytest.mark.parametrize("scene, assignment, rule", JOINT_CASES,
                         ids=[f"{c[0]} {c[1]}" for c in JOINT_CASES])
def test_a_value_in_range_that_breaks_a_rule_is_refused_with_the_rule(tmp_path, scene,
                                                                       assignment, rule):
    r = run("render", scene, "--set", assignment, "--size", SMALL, "--out", "j.png",
            cwd=tmp_path)
    line = usage_error(r)
    assert rule in line and "allowed" in line, line
    assert "context:" not in r.stderr  # refused before any GL work
    assert leftovers(tmp_path) == []


def test_params_lists_each_rule_beside_the_ranges_it_ties(tmp_path):
    r = run("params", "clouds", cwd=tmp_path)
    assert r.returncode == 0, r.stderr
    lines = {line.split(" = ")[0].strip(): line for line in r.stdout.splitlines() if " = " in line}
    for name in ("bake_shape.cells_g", "bake_shape.cells_b", "bake_shape.cells_a"):
        assert lines[name].endswith("an integer in [1, 128]; and bake_shape.cells_g < cells_b "
                                    "< cells_a (rising cell counts, G to A)"), lines[name]
    assert "; and clouds.max_height ≥ base_height + 1 m" in lines["clouds.base_height"]
    assert "; and clouds.max_height ≥ base_height + 1 m" in lines["clouds.max_height"]
    assert "; and" not in lines["clouds.density"]
