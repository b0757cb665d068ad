"""The theses' sections, one click from every parameter in the window's panel.

Every :class:`~app.params.Param` names the thesis section it comes from (``.section``, e.g.
``"spec/003 §2.9 b"``: the page ``docs/theory/003-toon-village.md``, its section §2.9 b, at the
anchor ``s-2.9-b``). The installed app must not need the pages, so ``tools/sections.py`` reads
them (:mod:`app.teach.theory`) into ``resources/sections.json``, committed, which
:func:`lookup` reads; ``tests/unit/test_sections.py`` fails when it is stale.

What an entry holds: the section's title (its heading without its number; a note on the
thesis's own numbering goes to ``source``), its heading level, and its own text (up to the next
anchored section, the markdown stripped; a section whose heading is followed at once by another
holds the whole section). Its math stays TeX (``$…$``) in the file and is shown as Unicode
(:attr:`Section.text`, the panel) or MathML (:func:`section_html`, the handouts). Equations are
entries too: ``spec/003 eq. 7.18``. A section's sub-letter reads ``§2.9(b)`` here.

The panel's model (:func:`build_headers`, :func:`filter_headers`) is here too, free of ImGui so
that it is tested without a window.
"""

from __future__ import annotations

import json
import re
from dataclasses import dataclass, field, replace
from functools import cache
from pathlib import Path
from typing import Any, Iterable, Sequence

from .. import RESOURCES
from ..params import Param, ParamSet
from . import theory

#: the committed section index (``tools/sections.py`` writes it)
INDEX = RESOURCES / "sections.json"
#: the format of :data:`INDEX` (bumped when its layout changes)
FORMAT = 2

OTHER = "Other"


@dataclass(frozen=True)
class Section:
    """One anchored section or equation of a theory page."""

    ref: str      # "spec/003 §2.9", "spec/003 §2.9(b)" or "spec/003 eq. 7.18"
    title: str    # "Grass"
    body: str     # its text, markdown stripped, math as $TeX$
    source: str = ""  # the thesis's own numbering when the heading gives it: "thesis §7.1"
    level: int = 2    # its heading's level on the page

    @property
    def spec(self) -> str:
        """``"spec/003"``."""
        return self.ref.split(" ", 1)[0]

    @property
    def number(self) -> str:
        """``"§2.9(b)"``, or an equation's number (of ``"spec/003 eq. 7.18"``)."""
        return self.ref.split(" ", 1)[1]

    @property
    def text(self) -> str:
        """The text as the panel shows it: math as Unicode."""
        return _unicode(self.body)

    @property
    def short_title(self) -> str:
        """The title before its first colon: ``"Day–night cycle"`` of "Day–night cycle:
        procedural skybox and reflection probe" (a panel's line is narrow)."""
        head = self.title.split(": ", 1)[0]
        return head if len(head) >= 4 else self.title

    @property
    def label(self) -> str:
        """``"§2.9 Grass"``: how a panel names the section (its short title)."""
        return f"{self.number} {self.short_title}"

    def summary(self, limit: int = 260) -> str:
        """The first sentences of the text, at most about ``limit`` characters (a tooltip)."""
        return summary(self.text, limit)


@cache
def _unicode(body: str) -> str:
    return theory.math_to_unicode(body)


def section_html(section: Section) -> str:
    """The section's text as HTML: escaped, its math as MathML (the handouts)."""
    return theory.math_to_html(section.body)


def summary(text: str, limit: int = 260) -> str:
    """The first sentences of ``text`` (bullets and line breaks read as one paragraph), cut
    at a sentence end when one comes before ``limit`` characters, else at a word with "…"."""
    flat = " ".join(line.strip().lstrip("•").strip() for line in text.splitlines()
                    if line.strip())
    if len(flat) <= limit:
        return flat
    cut = -1
    for m in re.finditer(r"[.!?](?=\s)", flat):
        if m.end() > limit:
            break
        cut = m.end()
    if cut >= limit // 3:
        return flat[:cut]
    head = flat[:limit].rsplit(" ", 1)[0]
    return head.rstrip(",;:") + " …"


@dataclass
class Index:
    """The section index: each thesis's title and citation, and its sections by ref, in the
    pages' order."""

    specs: dict[str, dict[str, str]] = field(default_factory=dict)
    sections: dict[str, Section] = field(default_factory=dict)

    def to_json(self) -> str:
        data = {
            "format": FORMAT,
            "generated_by": "tools/sections.py from Natura's theory pages (docs/theory/*.md)",
            "specs": self.specs,
            "sections": {ref: {"title": s.title, "source": s.source, "level": s.level,
                               "text": s.body}
                         for ref, s in self.sections.items()},
        }
        return json.dumps(data, ensure_ascii=False, indent=1) + "\n"

    @classmethod
    def from_json(cls, text: str) -> "Index":
        data = json.loads(text)
        if data.get("format") != FORMAT:
            raise ValueError(f"section index format {data.get('format')!r}: allowed {FORMAT}")
        sections = {ref: Section(ref, s["title"], s["text"], s.get("source", ""),
                                 int(s.get("level", 2)))
                    for ref, s in data["sections"].items()}
        return cls(data["specs"], sections)


@cache
def index() -> Index:
    """The committed index (read once). A missing or unreadable file gives an empty index: the
    panel then shows the bare refs, it does not fail."""
    try:
        return Index.from_json(INDEX.read_text(encoding="utf-8"))
    except (OSError, ValueError, KeyError, TypeError):
        return Index()


_REF = re.compile(r"^(spec/\d{3}) §((?:\d+|[A-Z])(?:\.(?:\d+|[A-Z]))*)(?:\(([a-z])\))?$")
_EQ = re.compile(r"^(spec/\d{3}) eq\.\s?(\S+)$")


def lookup(ref: str) -> Section | None:
    """The section or equation ``ref`` names (``"spec/002 §3.1"``, ``"spec/003 eq. 7.18"``),
    or None. A lettered item the page does not have falls back to its section, a number to its
    parent: ``§3.1.2`` → ``§3.1`` → ``§3``."""
    ref = normalise(ref)
    idx = index()
    e = _EQ.match(ref)
    if e:
        return idx.sections.get(f"{e.group(1)} eq. {e.group(2)}")
    m = _REF.match(ref)
    if not m:
        return None
    spec, number, letter = m.groups()
    if letter and ref in idx.sections:
        return idx.sections[ref]
    parts = number.split(".")
    while parts:
        key = f"{spec} §{'.'.join(parts)}"
        if key in idx.sections:
            return idx.sections[key]
        parts.pop()
    return None


def inside(section: Section) -> list[Section]:
    """The sections and equations inside ``section`` on its page (deeper headings before the
    next one of its level)."""
    out: list[Section] = []
    found = False
    for s in index().sections.values():
        if s is section or s.ref == section.ref:
            found = True
            continue
        if not found or s.spec != section.spec:
            if found:
                break
            continue
        if s.level <= section.level:
            break
        out.append(s)
    return out


def related(section: Section) -> list[Section]:
    """The sections next to ``section``: its parent, its lettered items and direct
    subsections, then what its page holds inside it (its equations)."""
    idx = index()
    out: list[Section] = []
    number = section.number
    if number.startswith("eq."):
        parent = None
    elif "(" in number:
        parent = idx.sections.get(section.ref.split("(")[0])
    elif "." in number:
        parent = idx.sections.get(f"{section.spec} {number.rsplit('.', 1)[0]}")
    else:
        parent = None
    if parent is not None:
        out.append(parent)
    for ref, s in idx.sections.items():
        rest = ref[len(section.ref):] if ref.startswith(section.ref) else ""
        if re.fullmatch(r"\([a-z]\)|\.(?:\d+|[A-Z])", rest):
            out.append(s)
    out += [s for s in inside(section) if s not in out]
    return out


def spec_title(spec: str) -> str:
    """``"spec/002"`` → the thesis's title (``""`` when the index does not know it)."""
    return index().specs.get(spec.strip(), {}).get("title", "")


def citation(spec: str) -> str:
    """``"spec/002"`` → the thesis's full citation (``""`` when the index does not know it)."""
    return index().specs.get(spec.strip(), {}).get("citation", "")


_TOKEN = re.compile(r"(spec/\d{3})|§\s?(\d+(?:\.\d+)*)(?:\s?\(([a-z])\)|\s([a-z])\b)?")


def normalise(ref: str) -> str:
    """``"spec/003 §2.9 b"`` → ``"spec/003 §2.9(b)"``; other text is returned stripped."""
    found = refs(ref)
    return found[0] if found else ref.strip()


def refs(section: str, default_spec: str = "") -> list[str]:
    """The thesis sections a ``Param.section`` names, normalised (``"spec/002 §1.2, §7"`` →
    ``["spec/002 §1.2", "spec/002 §7"]``). A ``§`` reads in the last ``spec/NNN`` of its
    clause (clauses are separated by ``;``); a clause that starts with a bare ``§`` is the
    effect's own thesis (``default_spec``); a ``§`` after another citation ("Hillaire 2020
    §4") is not a thesis section and gives nothing."""
    out: list[str] = []
    for clause in section.split(";"):
        spec = default_spec if clause.strip().startswith("§") else ""
        spec_seen = bool(spec)
        for m in _TOKEN.finditer(clause):
            if m.group(1):
                spec, spec_seen = m.group(1), True
                continue
            if not spec_seen or not spec:
                continue
            letter = m.group(3) or m.group(4)
            ref = f"{spec} §{m.group(2)}" + (f"({letter})" if letter else "")
            if ref not in out:
                out.append(ref)
    return out


@dataclass
class Group:
    """The parameters of one header that come from one thesis section."""

    key: str                    # the resolved ref, a citation outside the theses, or "" (Other)
    title: str                  # "§2.9(b) Textured billboard grass (final)", or "Other"
    section: Section | None
    params: list[Param]


@dataclass
class Header:
    """One collapsing header of the panel: a parameter group."""

    group: str                  # the parameter group ("grass", "time", "output")
    title: str
    spec: str                   # the thesis of the effect that owns the group ("" none)
    groups: list[Group]
    effect: str = ""            # the effect the group belongs to ("" for output, scene...)

    @property
    def params(self) -> list[Param]:
        return [p for g in self.groups for p in g.params]


def _number_key(number: str) -> tuple:
    m = re.match(r"§(\d+(?:\.(?:\d+|[A-Z]))*)(?:\(([a-z])\))?$", number)
    if not m:
        return (1e9, number)
    parts = tuple((0, int(x)) if x.isdigit() else (1, x) for x in m.group(1).split("."))
    return parts + (((-1, ""),) if not m.group(2) else ((0, m.group(2)),))


def group_key(param: Param, default_spec: str = "") -> tuple[str, Section | None]:
    """Where a parameter is shown: (key, section). The key is the resolved section's ref, else
    the first ref the index does not know, else the citation itself (a source outside the
    theses: "Hillaire 2020 §5.5"), else ``""`` (no section: "Other")."""
    found = refs(param.section, default_spec)
    for ref in found:
        s = lookup(ref)
        if s is not None:
            return s.ref, s
    if found:
        return found[0], None
    cited = param.section.split(";")[0].strip()
    return cited, None


def _sort_key(key: str) -> tuple:
    if not key:
        return (3,)
    m = re.match(r"^(spec/\d{3}) (§\S+)$", key)
    if m:
        return (0, m.group(1), _number_key(m.group(2)))
    return (2, [(0, int(t)) if t.isdigit() else (1, t) for t in re.split(r"(\d+)", key)])


def group_title(key: str, section: Section | None, spec: str = "") -> str:
    """A sub-group's title: ``"§2.9 Grass"`` (the thesis's spec named when it is not the
    header's), the citation itself when it is not a thesis's, or "Other"."""
    if not key:
        return OTHER
    if section is None:
        return key
    prefix = "" if section.spec == spec else f"{section.spec} "
    return f"{prefix}{section.label}"


def group_params(params: Iterable[Param], spec: str = "") -> list[Group]:
    """Parameters grouped by thesis section, in the pages' order (by spec, then section
    number), citations outside the theses next, "Other" (no section) last; each group keeps its
    parameters' declaration order."""
    groups: dict[str, Group] = {}
    for p in params:
        key, section = group_key(p, spec)
        if key not in groups:
            groups[key] = Group(key, group_title(key, section, spec), section, [])
        groups[key].params.append(p)
    return sorted(groups.values(), key=lambda g: _sort_key(g.key))


def _pretty(group: str) -> str:
    return group.replace("_", " ").capitalize()


def build_headers(params: ParamSet, effects: Sequence[Any] = (),
                  skip: Iterable[str] = ()) -> list[Header]:
    """The panel's headers for a scene: for each effect in the scene's order, its own group
    then its extra groups (``Effect.extra_groups``: Time after the sky, the bakes after the
    clouds); then the scene's own groups and Output. ``effects`` are the scene's effect
    classes or instances (``name``, ``title``, ``spec``, ``extra_groups``); parameters named
    in ``skip`` are left out, and a header left empty is dropped."""
    skip = set(skip)
    by_group = params.groups()
    order: list[tuple[str, str, str, str]] = []  # (group, title, spec, effect)
    seen: set[str] = set()
    for e in effects:
        if e.name not in seen:
            order.append((e.name, e.title or _pretty(e.name), e.spec, e.name))
            seen.add(e.name)
        for g in e.extra_groups:
            if g not in seen:
                title = "Time" if g == "time" else f"{_pretty(g)} — {e.title or _pretty(e.name)}"
                order.append((g, title, e.spec, e.name))
                seen.add(g)
    rest = [g for g in by_group if g not in seen and g != "output"]
    order += [(g, _pretty(g), "", "") for g in rest]
    order.append(("output", "Output", "", ""))
    headers = []
    for group, title, spec, effect in order:
        shown = [p for p in by_group.get(group, ()) if p.name not in skip]
        if shown:
            headers.append(Header(group, title, spec, group_params(shown, spec), effect))
    return headers


def haystack(param: Param, group: Group | None = None) -> str:
    """What a search looks through for one parameter: its name, doc, unit, its section's ref
    as written and the title of the group it is shown in (lower case)."""
    parts = [param.name, param.doc, param.unit, param.section]
    if group is not None:
        parts.append(group.title)
        if group.section is not None:
            parts += [group.section.ref, group.section.title]
    return " ".join(parts).lower()


def matches(param: Param, query: str, group: Group | None = None) -> bool:
    """Whether a search ``query`` matches a parameter: every word of it (case-insensitive) is
    in the parameter's name, short name, doc, or its thesis section's ref or title. An empty
    query matches everything."""
    words = query.lower().split()
    if not words:
        return True
    text = haystack(param, group)
    return all(w in text for w in words)


def filter_headers(headers: Sequence[Header], query: str) -> list[Header]:
    """The headers and groups that keep a parameter matching ``query`` (only those parameters);
    an empty query returns everything as it is."""
    if not query.split():
        return list(headers)
    out = []
    for h in headers:
        groups = []
        for g in h.groups:
            kept = [p for p in g.params if matches(p, query, g)]
            if kept:
                groups.append(replace(g, params=kept))
        if groups:
            out.append(replace(h, groups=groups))
    return out


def count(headers: Sequence[Header]) -> int:
    """Parameters shown under ``headers``."""
    return sum(len(g.params) for h in headers for g in h.groups)


def lesson_refs(text: str, default_spec: str = "") -> list[Section]:
    """The thesis sections a lesson names (its § button opens the first)."""
    out: list[Section] = []
    for ref in refs(text.replace(";", ","), default_spec):  # one clause: a bare § follows
        s = lookup(ref)                                        # the last spec/NNN named
        if s is not None and s not in out:
            out.append(s)
    return out


def notes_without(lesson: str | None, notes: Sequence[str]) -> list[str]:
    """An effect's panel notes less a line its lesson already says (the ocean's notes began
    with the lesson before lessons were shown above them)."""
    if not lesson:
        return list(notes)
    return [n for n in notes if not (n.strip() and lesson.strip().startswith(n.strip()))]


def build_index(root: Path = theory.THEORY) -> Index:
    """Every anchored section and equation of the pages under ``root`` as an :class:`Index`."""
    idx = Index()
    for spec, page in theory.pages(root).items():
        idx.specs[spec] = {"title": page.title, "heading": page.heading,
                           "citation": page.citation, "file": page.path.name}
        for e in page.entries.values():
            body = e.body or theory.section_body(page, e)
            idx.sections[e.ref] = Section(e.ref, e.title, body, e.source, e.level)
    return idx
