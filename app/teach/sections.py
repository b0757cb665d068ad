"""The thesis digests' sections, one click from every parameter in the window's panel.

Every :class:`~app.params.Param` names the thesis section it comes from (``.section``, e.g.
``"spec/003 §2.9 b"``: digest ``003-toon-village.md``, section 2.9, its item (b)). The digests
live beside the repository (``shared/spec/*.md``); the installed app must not need them, so
``tools/sections.py`` parses them (:func:`parse_digest`) into ``resources/sections.json``,
committed, which :func:`lookup` reads. ``tests/unit/test_sections.py`` regenerates it from the
digests when they are there, so it cannot go stale.

What a section holds: its title (the heading, without the thesis's own numbering, which goes to
``source``) and its text — the paragraphs of that section up to its first subsection, with the
markdown lightly stripped (bold, code spans, links, tables as ``a · b`` lines). A section whose
heading is followed at once by subsections lists them instead. Lettered items inside a section
(``**(b) Textured billboard grass (final).**``) are sections of their own: ``§2.9(b)``.

The panel's model is here too, free of ImGui so that it is tested without a window:
:func:`build_headers` groups a scene's parameters as the theses group them (one
:class:`Header` per parameter group — an effect, its extra groups, Time, Output — and inside
it one :class:`Group` per thesis section, in section order, "Other" last), and
:func:`filter_headers` keeps what a search matches.
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

#: the committed section index (``tools/sections.py`` writes it)
INDEX = RESOURCES / "sections.json"
#: the format of :data:`INDEX` (bumped when its layout changes)
FORMAT = 1

OTHER = "Other"


# ---- sections ---------------------------------------------------------------------------------

@dataclass(frozen=True)
class Section:
    """One section (or lettered item) of a thesis digest."""

    ref: str      # "spec/003 §2.9" or "spec/003 §2.9(b)"
    title: str    # "Grass"
    text: str     # its paragraphs, markdown lightly stripped
    source: str = ""  # where the digest took it from: the thesis's numbering, e.g. "§7.1"

    @property
    def spec(self) -> str:
        """``"spec/003"``."""
        return self.ref.split(" ", 1)[0]

    @property
    def number(self) -> str:
        """``"§2.9(b)"``."""
        return self.ref.split(" ", 1)[1]

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
    """The section index: thesis titles, sections by ref, and aliases (a ref in the thesis's
    own numbering that the digest's heading names, e.g. ``spec/003 §3.1`` → ``§2.2 Bump
    mapping (§3.1)``)."""

    specs: dict[str, dict[str, str]] = field(default_factory=dict)
    sections: dict[str, Section] = field(default_factory=dict)
    aliases: dict[str, str] = field(default_factory=dict)

    def to_json(self) -> str:
        data = {
            "format": FORMAT,
            "generated_by": "tools/sections.py from the thesis digests (shared/spec/*.md)",
            "specs": self.specs,
            "sections": {ref: {"title": s.title, "source": s.source, "text": s.text}
                         for ref, s in self.sections.items()},
            "aliases": self.aliases,
        }
        return json.dumps(data, ensure_ascii=False, indent=1) + "\n"

    @classmethod
    def from_json(cls, text: str) -> "Index":
        data = json.loads(text)
        if data.get("format") != FORMAT:
            raise ValueError(f"section index format {data.get('format')!r}: allowed {FORMAT}")
        sections = {ref: Section(ref, s["title"], s["text"], s.get("source", ""))
                    for ref, s in data["sections"].items()}
        return cls(data["specs"], sections, data.get("aliases", {}))


@cache
def index() -> Index:
    """The committed index (read once). A missing or unreadable file gives an empty index: the
    panel then shows the bare refs, it does not fail."""
    try:
        return Index.from_json(INDEX.read_text(encoding="utf-8"))
    except (OSError, ValueError, KeyError, TypeError):
        return Index()


_REF = re.compile(r"^(spec/\d{3}) §(\d+(?:\.(?:\d+|[A-Z]))*)(?:\(([a-z])\))?$")


def lookup(ref: str) -> Section | None:
    """The section ``ref`` names (``"spec/002 §3.1"``), or None. A lettered item falls back to
    its section, a number the digest does not have to the digest heading that carries it as
    the thesis's own number, then to its parent: ``§3.1.2`` → ``§3.1`` → ``§3``."""
    ref = normalise(ref)
    idx = index()
    m = _REF.match(ref)
    if not m:
        return None
    spec, number, letter = m.groups()
    if letter and ref in idx.sections:
        return idx.sections[ref]
    parts = number.split(".")
    first = True
    while parts:
        key = f"{spec} §{'.'.join(parts)}"
        if key in idx.sections:
            return idx.sections[key]
        if first and key in idx.aliases:
            return idx.sections.get(idx.aliases[key])
        first = False
        parts.pop()
    return None


def related(section: Section) -> list[Section]:
    """The sections next to ``section`` in the digest: its parent, then its lettered items
    and direct subsections (what the side window links to)."""
    idx = index()
    out: list[Section] = []
    number = section.number
    if "(" in number:
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
    return out


def spec_title(spec: str) -> str:
    """``"spec/002"`` → the thesis's title (``""`` when the index does not know it)."""
    return index().specs.get(spec.strip(), {}).get("title", "")


# ---- refs in Param.section --------------------------------------------------------------------

_TOKEN = re.compile(r"(spec/\d{3})|§\s?(\d+(?:\.\d+)*)(?:\s?\(([a-z])\)|\s([a-z])\b)?")


def normalise(ref: str) -> str:
    """``"spec/003 §2.9 b"`` → ``"spec/003 §2.9(b)"``; other text is returned stripped."""
    found = refs(ref)
    return found[0] if found else ref.strip()


def refs(section: str, default_spec: str = "") -> list[str]:
    """The digest sections a ``Param.section`` names, normalised (``"spec/002 §1.2, §7"`` →
    ``["spec/002 §1.2", "spec/002 §7"]``). A ``§`` reads in the last ``spec/NNN`` of its
    clause (clauses are separated by ``;``); a clause that starts with a bare ``§`` is the
    effect's own digest (``default_spec``); a ``§`` after another citation ("Hillaire 2020
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


def section_of(param: Param, default_spec: str = "") -> Section | None:
    """The first digest section of ``param`` that the index knows (None: none)."""
    for ref in refs(param.section, default_spec):
        s = lookup(ref)
        if s is not None:
            return s
    return None


# ---- the panel's model ------------------------------------------------------------------------

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
    spec: str                   # the digest of the effect that owns the group ("" none)
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
    """A sub-group's title: ``"§2.9 Grass"`` (the digest's spec named when it is not the
    header's), the citation itself when it is not a digest's, or "Other"."""
    if not key:
        return OTHER
    if section is None:
        return key
    prefix = "" if section.spec == spec else f"{section.spec} "
    return f"{prefix}{section.label}"


def group_params(params: Iterable[Param], spec: str = "") -> list[Group]:
    """Parameters grouped by thesis section, in the digests' order (by spec, then section
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
    """The digest sections a lesson names (its § button opens the first)."""
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


# ---- parsing the digests (tools/sections.py) --------------------------------------------------

_HEADING = re.compile(r"^(#{1,6})\s+(.*?)\s*$")
_NUMBERED = re.compile(r"^(\d+(?:\.\d+)*|[A-Z])\.?\s+(.*)$")
_ITEM = re.compile(r"^\*\*\(([a-z])\)\s*(.*?)\*\*\s*(.*)$")
_PAREN = re.compile(r"\s*\(([^()]*(?:\([^()]*\)[^()]*)*)\)")


def _inline(text: str) -> str:
    """Bold, italics, code spans, links and escapes of one line, stripped."""
    text = text.replace("\\*", "\0")
    text = re.sub(r"\[([^\]]+)\]\((?:[^()]|\([^)]*\))*\)", r"\1", text)  # [text](url)
    text = re.sub(r"`([^`]*)`", r"\1", text)
    text = re.sub(r"\*\*(.+?)\*\*", r"\1", text)
    text = re.sub(r"(?<![\w*])\*(?=\S)(.+?)(?<=\S)\*(?![\w*])", r"\1", text)
    text = re.sub(r"\\([_\[\]()#<>|])", r"\1", text)
    return text.replace("\0", "*")


def strip_markdown(lines: Sequence[str]) -> str:
    """Section lines as plain text: bullets as "•", tables as "a · b" rows, code blocks
    indented, rules and runs of blank lines dropped."""
    out: list[str] = []
    code = False
    for raw in lines:
        line = raw.rstrip()
        if line.lstrip().startswith("```"):
            code = not code
            continue
        if code:
            out.append("    " + line)
            continue
        stripped = line.strip()
        if re.fullmatch(r"-{3,}|\*{3,}|_{3,}", stripped):
            continue
        if stripped.startswith("|"):
            cells = [c.strip() for c in stripped.strip("|").split("|")]
            if all(re.fullmatch(r":?-{2,}:?", c) for c in cells if c):
                continue
            out.append(" · ".join(_inline(c) for c in cells))
            continue
        m = re.match(r"^(\s*)[-*+]\s+(.*)$", line)
        if m:
            depth = len(m.group(1).expandtabs(4)) // 2
            out.append("  " * depth + "• " + _inline(m.group(2)))
            continue
        if stripped.startswith(">"):
            stripped = stripped.lstrip("> ")
        out.append(_inline(stripped) if stripped else "")
    text = "\n".join(out)
    text = re.sub(r"\n{3,}", "\n\n", text)
    return text.strip("\n")


def clean_title(heading: str) -> tuple[str, str]:
    """A heading without its markers: (title, source). Parentheticals that say where the digest
    took it from (the thesis's § or chapter, "after Schneider …") become the source; a
    sentence after the title ("Contours / outlines (§8.2). Not solved …") is dropped."""
    text = _inline(heading).replace("[doc]", "").strip()
    sources = [m.group(1).strip() for m in _PAREN.finditer(text)]
    title = _PAREN.sub("", text).strip()
    title = re.split(r"(?<=\w)\.\s", title, maxsplit=1)[0].rstrip(" .:,")
    title = re.sub(r",\s*sources?\b.*$", "", title).strip()
    tail = re.search(r",\s*(sources?\b.*)$", _PAREN.sub("", text))
    if tail:
        sources.append(tail.group(1).strip(" ."))
    return title, "; ".join(sources)


def parse_digest(text: str, spec: str) -> tuple[dict[str, str], dict[str, Section],
                                                dict[str, str]]:
    """One digest (markdown) → (its thesis's title and file-level facts, its sections by ref,
    aliases: refs in the thesis's own numbering that a heading names in parentheses)."""
    lines = text.splitlines()
    title = ""
    headings: list[tuple[int, str, str]] = []  # (line, number or "", heading text)
    code = False
    for i, line in enumerate(lines):
        if line.lstrip().startswith("```"):
            code = not code
            continue
        m = _HEADING.match(line) if not code else None
        if not m:
            continue
        level, body = len(m.group(1)), m.group(2)
        if level == 1:
            if not title:
                q = re.search(r"[\"“]([^\"”]+)[\"”]", body)
                title = q.group(1) if q else body.split(":", 1)[-1].strip()
            headings.append((i, "", body))
            continue
        n = _NUMBERED.match(body)
        headings.append((i, n.group(1) if n else "", n.group(2) if n else body))
    sections: dict[str, Section] = {}
    alias_votes: dict[str, list[str]] = {}
    parent = ""
    for k, (start, number, body) in enumerate(headings):
        end = headings[k + 1][0] if k + 1 < len(headings) else len(lines)
        if not number:
            continue
        if number.isalpha():  # "### A. Maths helpers" under "## 6."
            if not parent:
                continue
            number = f"{parent}.{number}"
        elif "." not in number:
            parent = number
        ref = f"{spec} §{number}"
        head_title, source = clean_title(body)
        body_lines = lines[start + 1:end]
        sections[ref] = Section(ref, head_title, strip_markdown(body_lines), source)
        for m in re.finditer(r"§(\d+(?:\.\d+)*)(?![\d.–-])", source):
            if re.fullmatch(r"§\d+(?:\.\d+)*", source.strip()):
                alias_votes.setdefault(f"{spec} §{m.group(1)}", []).append(ref)
        items = [(j, _ITEM.match(line)) for j, line in enumerate(body_lines)]
        items = [(j, m) for j, m in items if m]
        for n, (j, m) in enumerate(items):
            stop = items[n + 1][0] if n + 1 < len(items) else len(body_lines)
            item_title, item_source = clean_title(m.group(2))
            after = m.group(3).strip()
            lead = _PAREN.match(after)  # "**(c) Gerstner waves** (Gerstner, 1802; …). The …"
            if lead:
                item_source = "; ".join(x for x in (item_source, lead.group(1).strip()) if x)
                after = after[lead.end():].lstrip(" .:")
            rest = [after] if after else []
            item_ref = f"{ref}({m.group(1)})"
            sections[item_ref] = Section(item_ref, item_title,
                                         strip_markdown(rest + body_lines[j + 1:stop]),
                                         item_source)
    # a section whose heading is followed at once by subsections: list them
    for ref, s in list(sections.items()):
        if s.text or "(" in s.number:
            continue
        children = [c for r, c in sections.items()
                    if r.startswith(ref + ".") and "(" not in c.number
                    and r[len(ref) + 1:].count(".") == 0]
        if children:
            listing = "\n".join(f"• {c.number} {c.title}" for c in children)
            sections[ref] = replace(s, text=f"Subsections:\n{listing}")
    aliases = {a: refs_[0] for a, refs_ in alias_votes.items()
               if len(set(refs_)) == 1 and a not in sections}
    return {"title": title}, sections, aliases


def build_index(spec_dir: Path) -> Index:
    """Parse every ``NNN-*.md`` digest of ``spec_dir`` into an :class:`Index`."""
    idx = Index()
    for path in sorted(Path(spec_dir).glob("[0-9][0-9][0-9]-*.md")):
        spec = f"spec/{path.name[:3]}"
        facts, sections, aliases = parse_digest(path.read_text(encoding="utf-8"), spec)
        idx.specs[spec] = {**facts, "file": path.name}
        idx.sections.update(sections)
        idx.aliases.update(aliases)
    return idx
