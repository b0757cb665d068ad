"""The documentation's command-line examples, each run once per test run (issue 26): the
walk-through (tests/cli/test_readme.py) and the dedicated tests that check an example's output (a
bench's JSON, charts and summary) share the same run instead of running the command twice.

The examples are the ```sh blocks of docs/commands.md's "Command line" section (the full
reference), then the README's own ```sh blocks of ``natura`` commands (every section but "Set up
and run", whose two commands .ci/run runs), in that order (``command_lines``).

The examples are split into lanes (``lanes``): every ``natura bench`` example alone in a folder
of its own, everything else in one folder in the pages' order. ``lane_result(i)`` runs lane
``i`` in the run's shared folder, or — when another test (or another pytest-xdist worker) has
started it already — waits for its result: the lane's folder holds a ``.claimed`` marker while it
runs and ``.result.json`` once done, whatever happened (a failure is a result too).

A numpy-only bench (``natura bench boat``) runs with a ``sitecustomize`` that makes creating a
GL context raise: the bench promises not to need one, and the example proves it.
"""

from __future__ import annotations

import json
import os
import re
import shlex
import subprocess
import textwrap
import time
from dataclasses import dataclass
from pathlib import Path

import pytest

from app import PROJECT_ROOT
from app.cli import NUMPY_BENCH_NAMES
from tests.helpers.cli import NATURA

README_PATH = PROJECT_ROOT / "README.md"
#: the full command reference: its "Command line" section holds most of the examples
COMMANDS_PATH = PROJECT_ROOT / "docs" / "commands.md"
#: the README's section whose ```sh blocks are the setup and test commands, not examples
SETUP_SECTION = "Set up and run"
#: how long one lane may take (the slowest bench on a loaded two-core runner, with margin)
LANE_TIMEOUT_S = 900


def sections(path: Path = README_PATH) -> dict[str, str]:
    """``## `` heading → that section's text (up to the next ``## ``), of the page ``path``."""
    text = path.read_text(encoding="utf-8")
    parts = re.split(r"^## (.+)\n", text, flags=re.M)
    return dict(zip(parts[1::2], parts[2::2]))


def blocks(language: str, section: str | None = None, path: Path = README_PATH) -> list[str]:
    """The ```LANGUAGE blocks of the page ``path`` (the README by default), or of one of its
    ``## `` sections."""
    text = path.read_text(encoding="utf-8") if section is None else sections(path)[section]
    return re.findall(rf"^```{language}\n(.*?)^```$", text, flags=re.S | re.M)


def _lines(block: str) -> list[str]:
    return [c for line in block.splitlines() if (c := line.split("#", 1)[0].strip())]


def readme_command_lines() -> list[str]:
    """The README's own examples: its ```sh lines outside "Set up and run"."""
    return [line for name, text in sections(README_PATH).items() if name != SETUP_SECTION
            for block in re.findall(r"^```sh\n(.*?)^```$", text, flags=re.S | re.M)
            for line in _lines(block)]


def command_lines() -> list[str]:
    """Every example, in order: docs/commands.md's "Command line" section, then the README's."""
    lines = [line for block in blocks("sh", "Command line", COMMANDS_PATH)
             for line in _lines(block)]
    return lines + readme_command_lines()


def lanes(commands: list[str] | None = None) -> list[list[str]]:
    """The examples split into lanes that may run at the same time, each in a folder of its own:
    every ``natura bench`` example alone (a bench reads no file an example writes, and its
    sweeps are the long part), everything else in one lane, in the pages' order."""
    commands = command_lines() if commands is None else commands
    main = [c for c in commands if shlex.split(c)[1:2] != ["bench"]]
    return [main] + [[c] for c in commands if c not in main]


def env(extra_path: Path | None = None) -> dict:
    e = {k: v for k, v in os.environ.items()
         if k not in ("DISPLAY", "WAYLAND_DISPLAY", "NATURA_SHADERS")}
    e["PYTHONPATH"] = os.pathsep.join(str(p) for p in (extra_path, PROJECT_ROOT,
                                                       os.environ.get("PYTHONPATH")) if p)
    return e


def no_gl_hook(folder: Path) -> Path:
    """A folder with a ``sitecustomize`` that makes creating a GL context raise."""
    hook = folder / "no-gl"
    hook.mkdir(parents=True, exist_ok=True)
    (hook / "sitecustomize.py").write_text(textwrap.dedent("""
        import moderngl

        def _refuse(*args, **kwargs):
            raise RuntimeError("a numpy bench created a GL context")

        moderngl.create_context = _refuse
        moderngl.create_standalone_context = _refuse
    """))
    return hook


@dataclass(frozen=True)
class Ran:
    command: str
    failure: str | None
    written: tuple[str, ...]
    seconds: float
    stdout: str


def _files(folder: Path) -> set[str]:
    return {p.relative_to(folder).as_posix() for p in folder.rglob("*")
            if not p.is_dir() and not p.name.startswith(".")}


def run_lane(commands: list[str], folder: Path, hooks: Path) -> list[Ran]:
    """Run ``commands`` in order in ``folder``."""
    out = []
    for command in commands:
        words = shlex.split(command)
        numpy_bench = words[1:2] == ["bench"] and words[2:3] and words[2] in NUMPY_BENCH_NAMES
        before = _files(folder)
        start = time.perf_counter()
        r = subprocess.run([*NATURA, *words[1:]], cwd=folder,
                           env=env(no_gl_hook(hooks) if numpy_bench else None),
                           capture_output=True, text=True, timeout=LANE_TIMEOUT_S)
        failure = None
        if r.returncode != 0:
            failure = f"`{command}` exited {r.returncode}: {r.stderr.strip()[-600:]}"
        elif "Traceback" in r.stderr:
            failure = f"`{command}` printed a traceback: {r.stderr.strip()[-600:]}"
        out.append(Ran(command, failure, tuple(sorted(_files(folder) - before)),
                       time.perf_counter() - start, r.stdout))
        if failure:
            break
    return out


def run_folder(tmp_path_factory) -> Path:
    """The run's folder (shared by pytest-xdist's workers, as ``session_cache`` is)."""
    base = tmp_path_factory.getbasetemp()
    if os.environ.get("PYTEST_XDIST_WORKER"):
        base = base.parent
    folder = base / "readme-examples"
    folder.mkdir(parents=True, exist_ok=True)
    return folder


def lane_result(tmp_path_factory, index: int) -> tuple[Path, list[Ran]]:
    """(lane ``index``'s folder, what each of its commands did): run here, or waited for."""
    commands = lanes()[index]
    root = run_folder(tmp_path_factory)
    folder = root / f"lane-{index}"
    result = root / f"lane-{index}.result.json"
    try:
        (root / f"lane-{index}.claimed").mkdir()  # atomic: one claimant per run
    except FileExistsError:
        deadline = time.monotonic() + LANE_TIMEOUT_S * max(1, len(commands))
        while not result.exists():
            if time.monotonic() > deadline:
                raise TimeoutError(f"example lane {index} ({commands[0]}) never finished") from None
            time.sleep(0.5)
        rows = json.loads(result.read_text())
        return folder, [Ran(**{**row, "written": tuple(row["written"])}) for row in rows]
    folder.mkdir()
    try:
        ran = run_lane(commands, folder, root / f"lane-{index}.hooks")
    except BaseException as exc:
        ran = [Ran(commands[0], f"the lane could not run: {exc!r}", (), 0.0, "")]
        raise
    finally:
        tmp = result.with_suffix(".tmp")
        rows = [{**r.__dict__, "written": list(r.written)} for r in ran]
        tmp.write_text(json.dumps(rows))
        os.replace(tmp, result)
    return folder, ran


def lane_fixture(func):
    """Flags a fixture that reads an example lane (put it under ``@pytest.fixture``): the tests
    using it are slow whatever one run measured (tests/helpers/tiers.py)."""
    func.readme_lane = True
    return func


def bench_lane(tmp_path_factory, command: str) -> tuple[Path, Ran]:
    """The bench example ``command`` (exactly as docs/commands.md has it), run once."""
    (index,) = [i for i, lane in enumerate(lanes()) if lane == [command]]
    folder, (ran,) = lane_result(tmp_path_factory, index)
    assert ran.failure is None, ran.failure
    return folder, ran


#: docs/commands.md's village bench: its five sections (app/bench/village.py) run quick once,
#: for the walk-through and for each section's own tests
VILLAGE_EXAMPLE = "natura bench village --repeat 2 --size 160x90"


def village_report(key: str):
    """A module's ``report`` fixture: section ``key`` as the README's `natura bench village`
    example wrote it (run once per test run): what a user's JSON holds."""

    @pytest.fixture(scope="module", name="report")
    @lane_fixture
    def report(tmp_path_factory):
        return village_section(tmp_path_factory, key)

    return report


def village_section(tmp_path_factory, key: str) -> dict:
    """Section ``key`` (grass, fog, water, vr, look) of docs/commands.md's village bench report."""
    folder, ran = bench_lane(tmp_path_factory, VILLAGE_EXAMPLE)
    (name,) = [n for n in ran.written if n.endswith(".json")]
    report = json.loads((folder / name).read_text())
    assert report["sweep"]["quick"] is True
    return report["sweep"][key]
