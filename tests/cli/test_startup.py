"""What a ``natura`` start imports and makes: the import graph, not a stopwatch (how long a start
takes is measured, docs/architecture.md "Measuring"; a timed unit test would only measure the
machine). ``import app.cli`` (argument parsing, --help, --version) loads no numpy, moderngl,
PIL or matplotlib; ``natura render sky`` imports the sky scene's module, not every scene's
effects; and a start with a warm cache reads the moon and the stars instead of generating them."""

from __future__ import annotations

import json
import os
import subprocess
import sys
import textwrap

from app import PROJECT_ROOT

HEAVY = ("numpy", "moderngl", "glcontext", "PIL", "matplotlib")


def _python(code: str, cwd, env: dict | None = None) -> dict:
    env = dict(os.environ if env is None else env)
    env["PYTHONPATH"] = os.pathsep.join(filter(None, [str(PROJECT_ROOT), env.get("PYTHONPATH")]))
    r = subprocess.run([sys.executable, "-c", textwrap.dedent(code)], cwd=cwd, env=env,
                       capture_output=True, text=True, timeout=120)
    assert r.returncode == 0, r.stderr[-2000:]
    return json.loads(r.stdout.strip().splitlines()[-1])


def test_importing_the_command_line_loads_no_numpy_gl_or_plotting(tmp_path):
    out = _python(f"""
        import json, sys
        import app.cli
        print(json.dumps([m for m in {HEAVY!r} if m in sys.modules]))
    """, tmp_path)
    assert out == [], f"`import app.cli` imports {out}"


def test_help_version_and_a_bad_command_load_no_gl_or_plotting(tmp_path):
    out = _python(f"""
        import contextlib, io, json, sys
        from app.cli import main
        codes = []
        for argv in (["--help"], ["--version"], ["render", "--help"], ["no-such-command"]):
            with contextlib.redirect_stdout(io.StringIO()), \\
                    contextlib.redirect_stderr(io.StringIO()):
                try:
                    codes.append(main(argv))
                except SystemExit as exc:
                    codes.append(exc.code)
        print(json.dumps({{"codes": codes, "heavy": [m for m in {HEAVY!r} if m in sys.modules]}}))
    """, tmp_path)
    # numpy: app.cli.main's last step imports app.imageio (to remove temporary files), which
    # imports numpy; nothing there needs GL or plotting
    assert out["codes"] == [0, 0, 0, 2] and set(out["heavy"]) <= {"numpy"}, out


def test_render_sky_imports_the_sky_scene_only(tmp_path):
    out = _python("""
        import json, sys
        from app.cli import main
        code = main(["render", "sky", "--size", "16x9", "--out", "x.png"])
        print(json.dumps({"code": code, "modules": sorted(m for m in sys.modules
                                                          if m.startswith("app."))}))
    """, tmp_path)
    assert out["code"] == 0 and (tmp_path / "x.png").is_file()
    modules = set(out["modules"])
    assert "app.scenes.sky" in modules
    others = {"app.scenes.ocean", "app.scenes.clouds", "app.scenes.planet",
              "app.scenes.materials", "app.effects.ocean", "app.effects.clouds",
              "app.bench", "app.ui.window"}
    assert not modules & others, sorted(modules & others)


def test_a_warm_cache_start_reads_the_moon_and_stars_instead_of_making_them(tmp_path):
    code = """
        import json
        from app.sim import textures
        made = []
        for kind, make in list(textures.GENERATORS.items()):
            textures.GENERATORS[kind] = lambda *a, _k=kind, _m=make, **kw: (made.append(_k),
                                                                             _m(*a, **kw))[1]
        from app.cli import main
        code = main(["render", "sky", "--size", "16x9", "--out", "x.png", "--force"])
        print(json.dumps({"code": code, "made": sorted(made)}))
    """
    env = dict(os.environ, NATURA_CACHE=str(tmp_path / "cache"))
    cold = _python(code, tmp_path, env)
    assert cold == {"code": 0, "made": ["moon", "stars"]}
    assert sorted(p.suffix for p in (tmp_path / "cache").iterdir()) == [".tex", ".tex"]
    warm = _python(code, tmp_path, env)
    assert warm == {"code": 0, "made": []}
