"""Every equation and section tag resolves to Natura's own theory pages (docs/theory/): a
student who meets ``spec/003 eq. 7.18`` in a shader, a docstring, a test or a document finds
that equation in ``docs/theory/003-*.md`` at the anchor ``eq-7.18`` (a section ``§2.9 a`` at
``s-2.9-a``). The pages cite their theses, and keep TeX inside math and notes to self out."""

from __future__ import annotations

import re
from pathlib import Path

from app import PROJECT_ROOT

THEORY = PROJECT_ROOT / "docs" / "theory"
#: a tag: ``spec/NNN eq. X`` or ``spec/NNN §X`` (a sub-letter after a space: ``§2.9 a``)
TAG = re.compile(r"spec/(\d{3}) (?:eq\. ((?:[A-Z]\.)?\d+(?:\.\d+)?)"
                 r"|§ ?((?:[A-Z]|\d+)(?:\.(?:[A-Z]|\d+))*(?: [a-z]\b)?))")
ANCHOR = re.compile(r'<a id="([^"]+)"></a>')
SOURCES = ("app", "glsl", "tests", "docs")
SUFFIXES = {".py", ".glsl", ".frag", ".vert", ".comp", ".geom", ".md", ".json", ".toml"}
#: what a student must never read on these pages: digests' notes to self
#: a thesis number that is not one: the made-up digest tests/unit/test_sections.py parses
FIXTURE = {"009"}
NOTES = re.compile(r"\[inference\]|scrape error|probably a typo|\bTODO\b|\bFIXME\b", re.I)


def pages() -> dict[str, Path]:
    return {p.name[:3]: p for p in sorted(THEORY.glob("[0-9][0-9][0-9]-*.md"))}


def anchors(path: Path) -> set[str]:
    return set(ANCHOR.findall(path.read_text(encoding="utf-8")))


def anchor_of(eq: str | None, section: str | None) -> str:
    if eq:
        return f"eq-{eq}"
    assert section is not None
    return "s-" + section.rstrip(".").replace(" ", "-")


def tags():
    """(file:line, tag, thesis, anchor) of every tag in the repository's code and documents."""
    files = [PROJECT_ROOT / "README.md"]
    for top in SOURCES:
        files += [p for p in (PROJECT_ROOT / top).rglob("*")
                  if p.suffix in SUFFIXES and "__pycache__" not in p.parts]
    for path in files:
        if path == Path(__file__) or path.name == "durations.json":  # (test ids, not citations)
            continue
        for i, line in enumerate(path.read_text(encoding="utf-8").splitlines(), 1):
            for m in TAG.finditer(line):
                yield (f"{path.relative_to(PROJECT_ROOT)}:{i}", m.group(), m.group(1),
                       anchor_of(m.group(2), m.group(3)))


def test_every_tag_resolves_to_an_anchor_of_a_theory_page():
    found = pages()
    held = {n: anchors(p) for n, p in found.items()}
    bad, seen = [], 0
    for where, tag, thesis, anchor in tags():
        seen += 1
        if thesis in FIXTURE and where.startswith("tests/unit/test_sections.py:"):
            continue
        if thesis not in found:
            bad.append(f"{where}: {tag!r}: no page docs/theory/{thesis}-*.md")
        elif anchor not in held[thesis]:
            bad.append(f"{where}: {tag!r}: no anchor {anchor!r} in "
                       f"{found[thesis].relative_to(PROJECT_ROOT)}")
    assert seen > 1000  # the code cites its theses everywhere: the scan found them
    assert not bad, f"{len(bad)} tags lead nowhere:\n" + "\n".join(sorted(set(bad))[:80])


def test_each_page_cites_its_thesis_and_holds_no_notes_to_self():
    found = pages()
    assert set(found) == {"000", "001", "002", "003", "004"}
    for n, path in found.items():
        text = path.read_text(encoding="utf-8")
        assert text.startswith("# "), path
        assert "Citation" in text[:3000], f"{path.name}: no citation near the top"
        notes = [f"{path.name}:{i}: {line.strip()[:80]}"
                 for i, line in enumerate(text.splitlines(), 1) if NOTES.search(line)]
        assert not notes, "\n".join(notes)
        # TeX only inside $…$ or $$…$$: outside math, no backslash commands
        outside = re.sub(r"\$\$.*?\$\$|\$[^$\n]+\$|`[^`\n]*`|```.*?```", "", text, flags=re.S)
        tex = [m.group() for m in re.finditer(r"\\[A-Za-z]+", outside)]
        assert not tex, f"{path.name}: TeX outside math: {sorted(set(tex))[:10]}"
        # every display equation is closed
        assert text.count("$$") % 2 == 0, f"{path.name}: an unclosed $$"


def test_anchors_are_unique_on_each_page():
    for path in pages().values():
        ids = ANCHOR.findall(path.read_text(encoding="utf-8"))
        dup = sorted({a for a in ids if ids.count(a) > 1})
        assert not dup, f"{path.name}: anchors used twice: {dup}"


def test_the_readme_credits_each_thesis_and_the_licence_is_there():
    readme = (PROJECT_ROOT / "README.md").read_text(encoding="utf-8")
    credits = readme[readme.index("## Credits and licence"):]
    for path in pages().values():  # each thesis's page is linked from the credits
        assert f"(docs/theory/{path.name})" in credits, path.name
    licence = (PROJECT_ROOT / "LICENSE").read_text(encoding="utf-8")
    assert licence.startswith("MIT License") and "Natura" in licence
