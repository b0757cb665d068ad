"""``natura explain TAG`` as a student runs it: a tag of each thesis prints its section of the
theory pages (math as Unicode) and every file:line that carries it, GLSL and numpy twins
apart; a malformed or unknown tag is one line naming it and what is allowed; every tag in the
repository resolves to text. And the handout ``natura report materials`` writes shows its
sections' math as MathML, with no TeX source and no note not meant for students."""

from __future__ import annotations

import re

import pytest

from app import PROJECT_ROOT
from app.teach import theory
from tests.helpers.cli import run, usage_error

TEX = re.compile(r"\\[A-Za-z]+|\\[,;!{}|]|_\{|\^\{|\$\$|\$[^$\n]*[\\_^{}][^$\n]*\$")
NOTES = re.compile(r"\[inference\]|scrape error|probably a typo|\bTODO\b|\bFIXME\b", re.I)


def _listed(stdout: str) -> dict[str, list[str]]:
    """The file:line lines under each kind's heading of the output's last part."""
    tail = stdout.split("\nWhere the code carries ", 1)[1]
    out: dict[str, list[str]] = {}
    kind = ""
    for line in tail.splitlines()[1:]:
        if line.startswith("  ") and not line.startswith("    "):
            kind = line.strip().split(":")[0]
            out[kind] = []
        elif line.startswith("    "):
            out[kind].append(line.strip())
    return out


#: a tag of each thesis, as the code writes it, and what its text must show
CASES = [
    ("spec/000 eq. 2.11", "time evolution", "h(k, t) = h₀(k) e^(iω(k) t)"),
    ("spec/001 eq. 3.2", "fBm", "fBm(x, H) = ∑ᵢ₌₀ⁿ aᵢ noise(fᵢ x)"),
    ("spec/002 §1.2", "Phase functions", "P_R(θ) = 3/(16π) · (1 + cos² θ)"),
    ("spec/003 eq. 7.18", "Height of a step", "step_y = stepₓ/(1 − stepₓ)"),
    ("spec/004 §1.5", "The noise, and where it bends the rings", "2⁻ⁱ"),
]


@pytest.mark.parametrize("tag, title, math", CASES)
def test_a_tag_of_each_thesis_prints_its_section_and_where_the_code_carries_it(
        tmp_path, tag, title, math):
    r = run("explain", tag, cwd=tmp_path)
    assert r.returncode == 0 and r.stderr == "", r.stderr
    out = r.stdout
    first = out.splitlines()[0]
    assert first.startswith(f"{tag} — ") and title in first
    page, entry = theory.find(tag)
    assert f"{page.path.relative_to(PROJECT_ROOT).as_posix()}:{entry.line}" in out
    assert math in out, out[:2000]
    assert not TEX.search(out.split("\nWhere the code carries ")[0]), "TeX source shown"
    listed = _listed(out)
    assert list(listed) == ["GLSL", "numpy twin", "Python", "tests"]
    assert listed["GLSL"] and listed["numpy twin"], listed  # the shader and its twin
    assert all(w.startswith("glsl/") for w in listed["GLSL"])
    assert all(w.startswith("app/sim/") for w in listed["numpy twin"])
    spec, anchor = theory.parse_tag(tag)
    for where in sum(listed.values(), []):  # each place really carries this tag
        path, line = where.rsplit(":", 1)
        text = (PROJECT_ROOT / path).read_text(encoding="utf-8").splitlines()[int(line) - 1]
        assert any((f"spec/{m.group(1)}", theory.anchor_of(m.group(2), m.group(3)))
                   == (spec, anchor) for m in theory.TAG.finditer(text)), where
    # and none is missed: as many as a scan of the three folders finds
    found = {f"{p}:{n}" for p, n, s, a in theory.scan() if (s, a) == (spec, anchor)
             and p not in theory.EXAMPLES}
    assert set(sum(listed.values(), [])) == found


def test_the_tag_may_be_unquoted_and_a_letter_in_brackets(tmp_path):
    a = run("explain", "spec/003", "§2.9", "a", cwd=tmp_path)
    b = run("explain", "spec/003 §2.9(a)", cwd=tmp_path)
    assert a.returncode == b.returncode == 0, (a.stderr, b.stderr)
    assert a.stdout == b.stdout and a.stdout.startswith("spec/003 §2.9 a — Geometry-shader grass")


#: tags no page has (built here so that the scan of the repository's tags does not meet them)
NO_EQ, NO_SECTION, NO_PAGE = ("spec/003 " + "eq. 99.1", "spec/003 " + "§42", "spec/007 " + "§1")


@pytest.mark.parametrize("args, culprit, allowed", [
    ([NO_EQ], f"'{NO_EQ}'", "allowed one it has (69: eq. 2.1 … eq. 9.2)"),
    ([NO_SECTION], f"'{NO_SECTION}'", "allowed one it has"),
    ([NO_PAGE], f"'{NO_PAGE}'", "allowed spec/000, spec/001"),
    (["Fresnel"], "'Fresnel'", "allowed spec/NNN eq. X or spec/NNN §X"),
    (["spec/3 eq 7.18x"], "'spec/3 eq 7.18x'", "allowed spec/NNN eq. X"),
])
def test_a_malformed_or_unknown_tag_is_one_line(tmp_path, args, culprit, allowed):
    line = usage_error(run("explain", *args, cwd=tmp_path))
    assert culprit in line and allowed in line, line
    assert len(line) <= 200


def test_no_tag_is_a_usage_error(tmp_path):
    r = run("explain", cwd=tmp_path)
    assert r.returncode == 2 and "TAG" in r.stderr and r.stdout == ""


def test_every_tag_in_the_repository_explains():
    """Each distinct tag in app/, glsl/, tests/ and docs/ finds its page and section, and
    its text reads without TeX (what ``natura explain`` prints for it)."""
    tags = {(s, a) for _, _, s, a in theory.scan(tops=("app", "glsl", "tests", "docs"))
            if s != "spec/009"}  # the made-up thesis of tests/unit/test_sections.py
    assert len(tags) > 150
    bad = []
    for spec, anchor in sorted(tags):
        tag = f"{spec} {theory.anchor_tag(anchor)}"
        try:
            page, entry = theory.find(tag)
        except Exception as exc:  # noqa: BLE001 — collected, reported together
            bad.append(f"{tag}: {exc}")
            continue
        text = theory.math_to_unicode(theory.section_body(page, entry))
        if not text.strip() or TEX.search(text) or NOTES.search(text):
            bad.append(f"{tag}: empty, TeX or a note in its text")
    assert not bad, "\n".join(bad[:30])
    assert not theory.UNKNOWN


def test_the_materials_handout_shows_math_as_mathml_and_no_tex(tmp_path):
    out = tmp_path / "handout"
    r = run("report", "materials", "--size", "32x18", "--rounds", "1", "--out", str(out),
            cwd=tmp_path)
    assert r.returncode == 0, r.stderr
    page = (out / "index.html").read_text(encoding="utf-8")
    assert page.count("<math") >= 5  # the sections' formulas, typeset by the browser
    assert not TEX.search(page) and not NOTES.search(page)  # MathML holds no TeX either
    shown = re.sub(r"<style.*?</style>|<math.*?</math>|<[^>]+>", "", page, flags=re.S)
    assert "digest" not in shown.lower()  # what the page says: Natura's theory pages
    assert "The noise, and where it bends the rings" in page
