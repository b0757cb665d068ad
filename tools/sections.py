"""Regenerate resources/sections.json — the thesis sections the window's panel and the HTML
handouts show — from Natura's theory pages (one per thesis in docs/theory/).

    python tools/sections.py            # write resources/sections.json
    python tools/sections.py --check    # exit 1 when it differs from what the pages give
    python tools/sections.py --theory DIR  # pages elsewhere

One entry per anchor of the pages (``<a id="s-2.9-a"></a>``, ``<a id="eq-7.18"></a>``): its
title, heading level and own text, math kept as TeX for the panel (Unicode) and the handouts
(MathML) to render. The installed app reads only the JSON (app/teach/sections.py);
tests/unit/test_sections.py fails when the committed file is not what this script writes.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

from app import PROJECT_ROOT
from app.imageio import write_text_atomic
from app.teach.sections import INDEX, build_index
from app.teach.theory import THEORY


def generate(theory_dir: Path = THEORY) -> str:
    """The text of resources/sections.json from the pages in ``theory_dir``."""
    return build_index(Path(theory_dir)).to_json()


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=(__doc__ or "").split("\n\n")[0])
    ap.add_argument("--theory", type=Path, default=THEORY,
                    help="folder of the theory pages (NNN-*.md; default docs/theory)")
    ap.add_argument("--check", action="store_true",
                    help="only compare: exit 1 when resources/sections.json is stale")
    args = ap.parse_args(argv)
    if not any(Path(args.theory).glob("[0-9][0-9][0-9]-*.md")):
        print(f"no theory pages (NNN-*.md) in {args.theory}: allowed --theory DIR",
              file=sys.stderr)
        return 2
    text = generate(args.theory)
    old = INDEX.read_text(encoding="utf-8") if INDEX.exists() else None
    name = INDEX.relative_to(PROJECT_ROOT) if INDEX.is_relative_to(PROJECT_ROOT) else INDEX
    if args.check:
        if old != text:
            print(f"{name} is stale: run python tools/sections.py", file=sys.stderr)
            return 1
        print(f"{name} is up to date")
        return 0
    if old == text:
        print(f"{name} already up to date")
        return 0
    write_text_atomic(INDEX, text, force=True)
    n = text.count('"level"')
    print(f"wrote {name} ({n} entries from {args.theory})")
    return 0


if __name__ == "__main__":
    sys.exit(main())
