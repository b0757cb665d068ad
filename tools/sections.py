"""Regenerate resources/sections.json — the thesis sections the window's panel shows beside
each parameter — from the thesis digests (shared/spec/*.md, beside the repository).

    python tools/sections.py            # write resources/sections.json
    python tools/sections.py --check    # exit 1 when it differs from what the digests give
    python tools/sections.py --spec DIR # digests elsewhere

The installed app reads only the JSON (app/teach/sections.py); tests/unit/test_sections.py
fails when the committed file is not what this script writes from the digests.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

from app import PROJECT_ROOT
from app.imageio import write_text_atomic
from app.teach.sections import INDEX, build_index

#: where the digests may be: inside the checkout (CI) or beside it (a workspace)
SPEC_DIRS = (PROJECT_ROOT / "shared" / "spec", PROJECT_ROOT.parent / "shared" / "spec")


def find_spec_dir() -> Path | None:
    """The first folder of :data:`SPEC_DIRS` that holds digests (None: none does)."""
    for d in SPEC_DIRS:
        if any(d.glob("[0-9][0-9][0-9]-*.md")):
            return d
    return None


def generate(spec_dir: Path) -> str:
    """The text of resources/sections.json from the digests in ``spec_dir``."""
    return build_index(spec_dir).to_json()


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--spec", type=Path, help="folder of the digests (NNN-*.md)")
    ap.add_argument("--check", action="store_true",
                    help="only compare: exit 1 when resources/sections.json is stale")
    args = ap.parse_args(argv)
    spec_dir = args.spec or find_spec_dir()
    if spec_dir is None or not any(Path(spec_dir).glob("[0-9][0-9][0-9]-*.md")):
        where = spec_dir or " or ".join(str(d) for d in SPEC_DIRS)
        print(f"no thesis digests (NNN-*.md) in {where}: allowed --spec DIR", file=sys.stderr)
        return 2
    text = generate(Path(spec_dir))
    old = INDEX.read_text(encoding="utf-8") if INDEX.exists() else None
    if args.check:
        if old != text:
            print(f"{INDEX.relative_to(PROJECT_ROOT)} is stale: run python tools/sections.py",
                  file=sys.stderr)
            return 1
        print(f"{INDEX.relative_to(PROJECT_ROOT)} is up to date")
        return 0
    if old == text:
        print(f"{INDEX.relative_to(PROJECT_ROOT)} already up to date")
        return 0
    write_text_atomic(INDEX, text, force=True)
    n = text.count('"title"')
    print(f"wrote {INDEX.relative_to(PROJECT_ROOT)} ({n} entries from {spec_dir})")
    return 0


if __name__ == "__main__":
    sys.exit(main())
