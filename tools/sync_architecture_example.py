"""Copy the example effect's files (tests/example/) into the code blocks of
docs/architecture.md's walk-through, as a project would have them (the one import that names
tests.example, and the "(in your own project: …)" notes, rewritten).

    python tools/sync_architecture_example.py

tests/gl/test_example_effect.py fails when the two differ.
"""

from __future__ import annotations

import re
import sys

from app import PROJECT_ROOT
from app.imageio import write_text_atomic

sys.path.insert(0, str(PROJECT_ROOT))  # the tests package, beside app/
from tests.gl.test_example_effect import BLOCK, DOC, FILES, as_in_a_project  # noqa: E402


def main() -> int:
    text = DOC.read_text(encoding="utf-8")

    def block(m: re.Match) -> str:
        path = m.group(1)
        if path not in FILES:
            raise SystemExit(f"docs/architecture.md names {path!r}: not a file of the example")
        lang = m.group(0).split()[0]
        return f"{lang} file={path}\n{as_in_a_project(FILES[path].read_text(encoding='utf-8'))}```"

    new = BLOCK.sub(block, text)
    if new == text:
        print("docs/architecture.md already shows the example's files")
        return 0
    write_text_atomic(DOC, new, force=True)
    print(f"updated {DOC.relative_to(PROJECT_ROOT)}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
