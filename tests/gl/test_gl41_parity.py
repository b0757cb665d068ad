"""Every scene and every method switch the docs name (README, docs/commands.md) draws the same
picture on a GL 4.1 core context — what macOS gives: no compute shaders, no base-instance or
indirect draws, GLSL 4.10 — as on this machine's 4.5 one. Mesa caps a context with environment
variables (tests/helpers/parity.py, ``GL41_ENV``), so two processes render the same jobs, one
capped, and the images are compared in 8 bits.

Tolerances: mean |Δ| ≤ 1.5 / 255 and the 99th percentile ≤ 24 / 255 — room for a compute path
and its fragment twin rounding differently in a few pixels, never for a missing object, a
wrong colour over a region or a black frame. A switch that cannot exist on 4.1 must instead be
refused in one line that names it (:data:`REFUSED_ON_41`).
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
from concurrent.futures import ThreadPoolExecutor

import numpy as np
import pytest

from app import PROJECT_ROOT
from app.cli import program_specs
from tests.helpers.fixtures import bake_cloud_noise
from tests.helpers.parity import GL41_ENV

SIZE = "96x54"  # small: a path that differs between the contexts shows at any size
MEAN_LIMIT = 1.5
P99_LIMIT = 24.0

#: name → (scene, --set values[, camera x, y, z, yaw, pitch]): the scenes' defaults and every
#: switch the README and docs/commands.md name
JOBS: dict[str, tuple] = {
    **{scene: (scene, []) for scene in ("sky", "probe", "materials", "planet", "clouds",
                                          "ocean", "noise", "maritime", "shading", "surfaces",
                                          "village")},
    "ocean-sine": ("ocean", ["ocean.model=sine"]),
    "ocean-gerstner": ("ocean", ["ocean.model=gerstner"]),
    "ocean-forward": ("ocean", ["ocean.shading=forward"]),
    "ocean-under": ("ocean", [], (0.0, -3.0, 0.0, 200.0, 50.0)),  # Snell's window
    "clouds-b": ("clouds", ["scene.model=b"]),
    "clouds-preetham": ("clouds", ["scene.sky=preetham"]),
    "noise-shape": ("noise", ["noise.view=shape"]),
    **{f"planet-{m}": ("planet", [f"planet.method={m}"])
       for m in ("brute_force", "lut", "hillaire")},
    **{f"grass-{m}": ("village", [f"grass.method={m}", "fog.plane=false"])
       for m in ("geometry", "billboard", "instanced")},
    **{f"shadows-{f}": ("surfaces", [f"surfaces.shadow_filter={f}"])
       for f in ("hard", "pcf", "pcss", "vsm")},
    "village-shadows-pcss": ("village", ["village.shadow_filter=pcss"]),
    **{f"transparency-{m}": ("surfaces", [f"surfaces.transparency={m}"])
       for m in ("wboit", "peeled")},
    "surfaces-ggx": ("surfaces", ["surfaces.specular_model=ggx"]),
    "surfaces-perfect": ("surfaces", ["surfaces.reflection=perfect"]),
    **{f"parallax-{m}": ("shading", [f"shading.parallax_mode={m}"]) for m in (0, 2, 3, 4)},
    "toon-ramp": ("shading", ["shading.toon=3", "shading.contour=hull"]),
    "contour-sobel": ("shading", ["shading.contour=edges_sobel"]),
    # the compute FFT on 4.5 against its fragment twin on 4.1 (auto picks fragment there)
    "ocean-fft-compute": ("ocean", ["ocean.fft_path=compute"]),
}
#: jobs whose 4.1 run uses other settings (the same picture by its 4.1 path)
ON_41 = {"ocean-fft-compute": ["ocean.fft_path=auto"]}
#: switches that cannot exist on 4.1, and the words their one-line refusal must hold
REFUSED_ON_41 = {"ocean-fft-explicit-compute": ("ocean.fft_path=compute", "compute shaders")}
#: set before each job's own values, on both contexts: the same shaders and paths at smaller
#: sizes. At their defaults the sky's and the lab's reflection cubemaps (six 128² faces, twenty
#: times the 96×54 frame's pixels, and the lab's prefiltered levels) and the planet's 2048²
#: ground-noise bake were most of a job's time on llvmpipe
CHEAP = ("sky.cubemap_size=16", "surfaces.probe_size=64", "planet.ground_noise_size=256")


def _cheap(scene: str) -> list[str]:
    from app.runtime import scene_params

    params = scene_params(scene)
    return [s for s in CHEAP if s.split("=", 1)[0] in params]


def test_the_jobs_cover_every_scene_and_each_switch_with_every_choice():
    """The matrix itself (no render): every scene's default, and each switch the docs name
    with every value it can take that differs on the two contexts' paths."""
    from app.runtime import scene_params
    from app.scenes import SCENES

    assert {job[0] for job in JOBS.values()} == set(SCENES)
    assert set(SCENES) <= set(JOBS)
    for scene, sets, *camera in JOBS.values():
        params = scene_params(scene, sets=sets)  # every setting exists and is in range
        assert all(params[s.split("=", 1)[0]] is not None for s in sets)
        assert not camera or len(camera[0]) == 5
    models = {sets[0] for scene, sets, *_ in JOBS.values() if scene == "ocean" and sets}
    assert {"ocean.model=sine", "ocean.model=gerstner", "ocean.shading=forward"} <= models
    grass = {sets[0] for scene, sets, *_ in JOBS.values() if sets and sets[0].startswith("grass")}
    assert grass == {f"grass.method={m}" for m in ("geometry", "billboard", "instanced")}
    assert set(ON_41) <= set(JOBS) and not set(REFUSED_ON_41) & set(JOBS)


def _render(out, jobs, env_extra):
    out.mkdir()
    path = out / "jobs.json"
    path.write_text(json.dumps(jobs))
    env = dict(os.environ, **env_extra)
    env["PYTHONPATH"] = os.pathsep.join(filter(None, [str(PROJECT_ROOT),
                                                      env.get("PYTHONPATH")]))
    done = subprocess.run([sys.executable, "-m", "tests.helpers.parity", str(out), str(path),
                           SIZE], env=env, cwd=PROJECT_ROOT, capture_output=True, text=True,
                          timeout=600)
    assert done.returncode == 0, done.stderr[-2000:]
    return json.loads((out / "run.json").read_text())


@pytest.fixture(scope="module")
def runs(tmp_path_factory, gl_ctx):
    # the cloud noise bakes the jobs sample, made once into the run's cache before the two
    # processes start (side by side on an empty cache, both would bake it). Its bytes do not
    # depend on the bake's path (tests/gl/test_bakes.py checks the fragment path on a 4.1
    # context against the compute one), so the pictures are the same.
    bake_cloud_noise(gl_ctx)
    base = tmp_path_factory.mktemp("parity")
    jobs45 = [[name, job[0], _cheap(job[0]) + job[1], *job[2:]] for name, job in JOBS.items()]
    jobs41 = [[name, job[0], _cheap(job[0]) + ON_41.get(name, job[1]), *job[2:]]
              for name, job in JOBS.items()]
    jobs41.append(["ocean-fft-explicit-compute", "ocean",
                   _cheap("ocean") + ["ocean.fft_path=compute"]])
    with ThreadPoolExecutor(2) as pool:  # the two processes side by side
        r45 = pool.submit(_render, base / "gl45", jobs45, {})
        r41 = pool.submit(_render, base / "gl41", jobs41, GL41_ENV)
        return base, r45.result(), r41.result()


def test_the_runs_got_the_contexts_they_asked_for(runs):
    _, r45, r41 = runs
    assert "OpenGL 4.5" in r45["context"]
    assert "OpenGL 4.1" in r41["context"]
    assert r45["refused"] == {}


@pytest.mark.parametrize("name", sorted(JOBS))
def test_same_picture_on_41_as_on_45(runs, name):
    base, _, r41 = runs
    assert name not in r41["refused"], r41["refused"].get(name)
    a = np.load(base / "gl45" / f"{name}.npy").astype(np.float64)
    b = np.load(base / "gl41" / f"{name}.npy").astype(np.float64)
    assert a.std() > 2.0  # a picture, not a flat frame, on either side
    diff = np.abs(a - b)
    assert diff.mean() <= MEAN_LIMIT, f"{name}: mean |Δ| {diff.mean():.2f}/255"
    assert np.percentile(diff, 99) <= P99_LIMIT, \
        f"{name}: p99 |Δ| {np.percentile(diff, 99):.1f}/255"


def test_what_cannot_exist_on_41_is_refused_in_one_line(runs):
    _, _, r41 = runs
    for name, words in REFUSED_ON_41.items():
        message = r41["refused"][name]
        assert "\n" not in message and len(message) < 200
        for word in words:
            assert word.split("=")[0] in message, (name, message)


def test_no_program_is_built_that_shaders_check_does_not_know(runs):
    """Every variant the renders compiled, on both contexts, is one `natura shaders check`
    (and its --strict pass) compiles."""
    _, r45, r41 = runs
    known = {(s.name, tuple(sorted(dict(s.defines).items())),
              tuple(sorted((k, v) for k, v in s.stages().items() if v)))
             for s in program_specs()}
    for run in (r45, r41):
        for name, defines, stages in run["programs"]:
            key = (name, tuple(map(tuple, defines)), tuple(map(tuple, stages)))
            assert key in known, key
