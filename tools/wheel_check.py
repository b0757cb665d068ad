"""Do wheels of every dependency exist for the students' platforms, at the versions installed here?

    python tools/wheel_check.py [--python 3.11,3.12,3.13] [--markdown]

For Natura and its test extra, the whole dependency tree as this environment resolved it
(``importlib.metadata``: exactly what ``pip install -e '.[test]'`` chose), then for each
platform — macOS arm64, macOS x86_64, Windows x64 — and each Python version, ``pip download
--only-binary=:all: --platform … --python-version …`` of that exact version, one package at a
time (so a missing wheel is named, not a resolver failure). A package only on PyPI as a source
distribution would need a compiler on the student's machine: it shows as "no wheel".

For macOS the oldest release each wheel accepts is read from its file name (``macosx_14_0``).
The "Wheels" table of docs/commands.md is this script's ``--markdown`` output (a maintainer runs
it; it needs PyPI). Exit 1 when any wheel is missing.
"""

from __future__ import annotations

import argparse
import importlib.metadata as md
import re
import subprocess
import sys
import tempfile
from pathlib import Path

from packaging.requirements import Requirement

#: (column, pip's --platform tags: the newest one first; pip accepts the older compatible ones)
PLATFORMS = (
    ("macOS arm64", ("macosx_15_0_arm64",)),
    ("macOS x86_64", ("macosx_15_0_x86_64",)),
    ("Windows x64", ("win_amd64",)),
)
_MAC = re.compile(r"macosx_(\d+)_(\d+)_")


def dependency_tree(name: str = "natura", extras: tuple[str, ...] = ("test",)) -> dict[str, str]:
    """Every distribution ``name[extras]`` needs, as installed here: name → version."""
    seen: dict[str, str] = {}

    def walk(dist_name: str, with_extras: tuple[str, ...]) -> None:
        dist = md.distribution(dist_name)
        key = dist.metadata["Name"].lower()
        if key in seen:
            return
        seen[key] = dist.version
        for text in dist.requires or []:
            req = Requirement(text)
            if req.marker is not None and not any(
                    req.marker.evaluate({"extra": e}) for e in (*with_extras, "")):
                continue
            try:
                walk(req.name, tuple(req.extras))
            except md.PackageNotFoundError:  # a requirement for another platform
                continue

    walk(name, extras)
    seen.pop(name, None)
    return dict(sorted(seen.items()))


def wheel_for(package: str, version: str, platforms: tuple[str, ...], python: str) -> str | None:
    """The wheel file pip downloads for that platform and Python, or None."""
    with tempfile.TemporaryDirectory() as tmp:
        args = [sys.executable, "-m", "pip", "download", "-q", "--no-deps",
                "--only-binary=:all:", "--python-version", python, "--implementation", "cp",
                "-d", tmp, f"{package}=={version}"]
        for tag in platforms:
            args += ["--platform", tag]
        done = subprocess.run(args, capture_output=True, text=True, timeout=600)
        files = list(Path(tmp).glob("*.whl"))
        return files[0].name if done.returncode == 0 and files else None


def describe(wheel: str | None) -> str:
    if wheel is None:
        return "no wheel"
    if wheel.endswith("-none-any.whl"):
        return "any"
    m = _MAC.search(wheel)
    return f"macOS {m[1]}+" if m else "yes"


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--python", default="3.11,3.12,3.13")
    ap.add_argument("--markdown", action="store_true", help="the table in docs/commands.md")
    args = ap.parse_args(argv)
    pythons = args.python.split(",")
    tree = dependency_tree()
    missing = 0
    rows = []
    for package, version in tree.items():
        cells = []
        for _, tags in PLATFORMS:
            verdicts = {describe(wheel_for(package, version, tags, py)) for py in pythons}
            if "no wheel" in verdicts:
                missing += 1
            cells.append(" / ".join(sorted(verdicts)))
        rows.append((package, version, cells))
        if not args.markdown:
            print(f"{package:22} {version:12} " + "  ".join(f"{c:14}" for c in cells), flush=True)
    if args.markdown:
        head = ["package", "version"] + [name for name, _ in PLATFORMS]
        print("| " + " | ".join(head) + " |")
        print("|" + "---|" * len(head))
        for package, version, cells in rows:
            print(f"| {package} | {version} | " + " | ".join(cells) + " |")
        print(f"\nPython {', '.join(pythons)}; {missing} missing.")
    return 1 if missing else 0


if __name__ == "__main__":
    sys.exit(main())
