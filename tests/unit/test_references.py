"""What the code says about itself stays findable and true (docs/architecture.md, "Tags").

* one tag form per thesis equation, ``spec/NNN eq. X.Y`` (annex equations ``spec/000 eq. B.2``),
  so one grep finds every function implementing it: no plural "eqs.", no ranges, no bare
  "(4.18)" in comments; an equation of a paper is tagged with its author and year
  (``Hillaire 2020 eq. 9``, ``Tessendorf 2001 eq. 26``);
* no references to issue numbers, nor to files outside the repository, in code, shaders and
  parameter metadata;
* every repository path and every ``app.…`` name a comment or docstring mentions exists.
"""

from __future__ import annotations

import functools
import importlib
import io
import re
import tokenize
from pathlib import Path

from app import PROJECT_ROOT

CODE = [p for p in (PROJECT_ROOT / "app").rglob("*.py") if "__pycache__" not in p.parts]
SHADERS = [p for p in (PROJECT_ROOT / "glsl").rglob("*")
           if p.suffix in (".glsl", ".frag", ".vert", ".comp")]
PRESETS = list((PROJECT_ROOT / "resources").rglob("*.toml"))

#: what must stand right before an "eq." — a thesis digest or a paper's year
TAG_PREFIX = re.compile(r"(?:spec/\d{3}|\b(?:19|20)\d{2}) $")
#: the equation number after it: "eq. 4.18", "eq. B.2" (theses), "eq. 9" (papers)
TAG_NUMBER = re.compile(r"eq\. [A-Z]?\d+(?:\.\d+)?(?![\d–-])")
EQ = re.compile(r"\b[Ee]qs?\b\.?\s*\(?[A-Z]?\d")
PLURAL = re.compile(r"\b[Ee]qs\b")
BARE = re.compile(r"\((?:[A-Z]\.)?\d{1,2}\.\d{1,2}\)")
ISSUE = re.compile(r"\b[Ii]ssues? ?#?\d+")
OUTSIDE = re.compile(r"\.\./shared|\bseeds/|DESIGN\.md")
PATH = re.compile(r"(?<![\w./])(?:app|glsl|tests|tools|resources|docs)/[\w./*-]*[\w*]")
DOTTED = re.compile(r"(?<![\w.])app(?:\.\w+)+")


def python_text(path: Path) -> list[tuple[int, str]]:
    """(line, text) of every comment and string literal (docstrings and Param metadata)."""
    out = []
    tokens = tokenize.generate_tokens(io.StringIO(path.read_text(encoding="utf-8")).readline)
    for tok in tokens:
        if tok.type in (tokenize.COMMENT, tokenize.STRING):
            out.append((tok.start[0], tok.string))
        elif tok.type == getattr(tokenize, "FSTRING_MIDDLE", -1):
            out.append((tok.start[0], tok.string))
    return out


def glsl_comments(path: Path) -> list[tuple[int, str]]:
    out = []
    in_block = False
    for i, line in enumerate(path.read_text(encoding="utf-8").splitlines(), 1):
        if in_block:
            end = line.find("*/")
            out.append((i, line if end < 0 else line[:end]))
            in_block = end < 0
            continue
        if "//" in line:
            out.append((i, line[line.index("//"):]))
        if "/*" in line:
            rest = line[line.index("/*"):]
            out.append((i, rest))
            in_block = "*/" not in rest
    return out


@functools.cache
def texts() -> tuple[tuple[Path, int, str], ...]:
    """Every comment and string of the code and the shaders, read once for the module's four
    checks (tokenizing app/ is most of each check's time)."""
    return (tuple((path, line, text) for path in CODE for line, text in python_text(path))
            + tuple((path, line, text) for path in SHADERS for line, text in glsl_comments(path)))


def where(path: Path, line: int) -> str:
    return f"{path.relative_to(PROJECT_ROOT)}:{line}"


def test_equation_tags_have_one_form():
    bad = []
    for path, line, text in texts():
        for m in PLURAL.finditer(text):
            bad.append(f"{where(path, line)}: plural {text[m.start():m.end() + 12]!r}: "
                       "tag each equation")
        for m in EQ.finditer(text):
            start = m.start()
            if not TAG_PREFIX.search(text[:start]) or not TAG_NUMBER.match(text, start):
                seen = text[max(0, start - 9):m.end() + 6]
                bad.append(f"{where(path, line)}: {seen!r} is not 'spec/NNN eq. X.Y'")
        for m in BARE.finditer(text):
            bad.append(f"{where(path, line)}: bare equation number {m.group()!r}: "
                       "write 'spec/NNN eq. X.Y'")
    assert not bad, f"{len(bad)} equation references not in the tag form:\n" + "\n".join(bad)


def test_no_issue_numbers_or_files_outside_the_repository():
    bad = [f"{where(path, line)}: {m.group()!r}" for path, line, text in texts()
           for rx in (ISSUE, OUTSIDE) for m in rx.finditer(text)]
    for path in PRESETS:
        for i, line in enumerate(path.read_text(encoding="utf-8").splitlines(), 1):
            bad += [f"{where(path, i)}: {m.group()!r}"
                    for rx in (ISSUE, OUTSIDE) for m in rx.finditer(line)]
    assert not bad, "\n".join(bad)


def _exists(ref: str) -> bool:
    ref = ref.rstrip(".")
    if list((PROJECT_ROOT / "glsl").glob(ref + ".*")):  # a program name (tests/noise_probe)
        return True
    if "*" in ref or "<" in ref:
        return bool(list(PROJECT_ROOT.glob(ref))) or "<" in ref
    return (PROJECT_ROOT / ref).exists()


def test_mentioned_paths_exist():
    bad = []
    for path, line, text in texts():
        for m in PATH.finditer(text):
            if text[m.end():m.end() + 1] in ("-", "<", "{"):  # a pattern such as clouds-<name>.toml
                continue
            if not _exists(m.group()):
                bad.append(f"{where(path, line)}: {m.group()!r} does not exist")
    assert not bad, "stale path references:\n" + "\n".join(bad)


def _resolves(name: str) -> bool:
    parts = name.split(".")
    for cut in range(len(parts), 0, -1):
        try:
            obj = importlib.import_module(".".join(parts[:cut]))
        except ImportError:
            continue
        for attr in parts[cut:]:
            if not hasattr(obj, attr):
                return False
            obj = getattr(obj, attr)
        return True
    return False


def test_mentioned_app_names_exist():
    bad = []
    for path, line, text in texts():
        for m in DOTTED.finditer(text):
            if not _resolves(m.group()):
                bad.append(f"{where(path, line)}: {m.group()!r} does not exist")
    assert not bad, "stale module references:\n" + "\n".join(bad)
