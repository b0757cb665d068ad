"""``natura exercise list | start NAME DIR | check DIR``, run as a student runs them: every
exercise solved with Natura's own body passes, and a plausible wrong body (the exercise's first
known wrong answer) fails with that answer's hint; ``start`` never overwrites; a compile error
is named by file and line."""

from __future__ import annotations

import re
from pathlib import Path

import numpy as np
import pytest

from app.teach import exercise as ex_mod
from tests.helpers.cli import messages, run, usage_error
from tests.helpers.images import read_png

NAMES = ex_mod.names()


def _solve(folder: Path, ex: ex_mod.Exercise, body: str) -> None:
    """What a student does: write a body into the copy's function (every overload)."""
    ex_mod.write_body(folder / "glsl", ex, body)


def _reference_body(ex: ex_mod.Exercise) -> str:
    """The body of Natura's own function (of its first definition)."""
    text = (ex_mod.DEFAULT_SHADER_ROOT / ex.file).read_text(encoding="utf-8")
    _, start, end = ex_mod.function_spans(text, ex.function)[0]
    return text[start:end]


def _words(text: str) -> str:
    return " ".join(text.split())


def test_list_shows_every_exercise_over_the_five_theses(tmp_path):
    r = run("exercise", "list", cwd=tmp_path)
    assert r.returncode == 0, r.stderr
    shown = re.findall(r"^(\S+) ", r.stdout, re.M)
    assert shown == NAMES and len(NAMES) >= 10
    theses = {ex.thesis for ex in ex_mod.all_exercises()}
    assert theses == {"000", "001", "002", "003", "004"}
    for ex in ex_mod.all_exercises():  # each names its function and its theory page's anchor
        assert f"glsl/{ex.file}: {ex.function}" in r.stdout
        page, anchor = ex_mod.theory_anchor(ex.tag, ex.name)
        assert f"#{anchor}" in r.stdout and page.is_file()
        assert ex.wrong and all(w.hint.strip() for w in ex.wrong)


@pytest.mark.slow  # three renders of a scene and two to four more on llvmpipe: 5 to 25 s
@pytest.mark.parametrize("name", NAMES)
def test_the_reference_body_passes_and_a_wrong_one_fails_with_its_hint(tmp_path, name):
    ex = ex_mod.find(name)
    r = run("exercise", "start", name, "work", cwd=tmp_path)
    assert r.returncode == 0, r.stderr
    folder = tmp_path / "work"
    assert f"work/glsl/{ex.file}:" in r.stdout and ex.theory() in r.stdout
    blanked = (folder / "glsl" / ex.file).read_text(encoding="utf-8")
    assert _reference_body(ex) not in blanked  # the function really is blank
    assert f"Theory: {ex.theory()}" in blanked
    expected = read_png(folder / "expected.png")
    assert expected.shape == (ex.size[1], ex.size[0], 3) and expected.std() > 2.0

    _solve(folder, ex, _reference_body(ex))
    r = run("exercise", "check", "work", cwd=tmp_path)
    assert r.returncode == 0, (r.stdout, r.stderr)
    assert f"exercise {name}: PASS" in r.stdout and "mean error 0.0000" in r.stdout
    difference = read_png(folder / "difference.png")
    assert difference.shape[1] == 3 * ex.size[0] + 4

    wrong = ex.wrong[0]
    _solve(folder, ex, wrong.body)
    r = run("exercise", "check", "work", cwd=tmp_path)
    assert r.returncode == 1, (r.stdout, r.stderr)
    assert f"exercise {name}: FAIL" in r.stdout
    assert f"likely mistake: {_words(wrong.hint)}" in r.stdout, r.stdout
    assert f"theory: {ex.theory()}" in r.stdout
    if re.search(r"mean error [0-9.]+ \(>", r.stdout):  # the picture differs: it shows where
        heat = read_png(folder / "difference.png")[:, 2 * ex.size[0] + 4:]
        assert heat.max() > 100
    else:  # only the probe tells them apart
        assert re.search(r"probe of .* worst error \S+ \(>", r.stdout), r.stdout


def test_a_compile_error_is_named_by_file_and_line(tmp_path):
    ex = ex_mod.find("stepped-toon")
    assert run("exercise", "start", ex.name, "work", cwd=tmp_path).returncode == 0
    _solve(tmp_path / "work", ex, "\n    return x <= 0.45 ? 0.2 : ;\n")
    text = (tmp_path / "work" / "glsl" / ex.file).read_text(encoding="utf-8")
    line = text[:text.index("? 0.2 : ;")].count("\n") + 1
    r = run("exercise", "check", "work", cwd=tmp_path)
    assert r.returncode == 1 and "Traceback" not in r.stderr
    assert any(m.startswith(f"natura: work/glsl/{ex.file}:{line}:") or
               f"work/glsl/{ex.file}:{line}:" in m for m in messages(r.stderr)), r.stderr


def test_start_never_overwrites_and_check_wants_an_exercise(tmp_path):
    mine = tmp_path / "mine"
    mine.mkdir()
    (mine / "notes.txt").write_text("my notes")
    line = usage_error(run("exercise", "start", "schlick-fresnel", "mine", cwd=tmp_path))
    assert "already exists" in line and "nothing is overwritten" in line
    assert [p.name for p in mine.iterdir()] == ["notes.txt"]
    assert (mine / "notes.txt").read_text() == "my notes"
    line = usage_error(run("exercise", "check", "mine", cwd=tmp_path))
    assert "holds no exercise" in line and "natura exercise start" in line
    line = usage_error(run("exercise", "start", "no-such", "new", cwd=tmp_path))
    assert "unknown exercise 'no-such'" in line and "natura exercise list" in line
    assert not (tmp_path / "new").exists()
    assert sorted(p.name for p in tmp_path.iterdir()) == ["mine"]  # no temporary left


def test_start_refuses_a_folder_it_cannot_make_before_any_work(tmp_path):
    """As ``shaders copy`` and ``report --out``: a name longer than the file system allows, or
    a folder in one that does not exist, is one line naming it, before the expected render."""
    line = usage_error(run("exercise", "start", "schlick-fresnel", "e" * 300, cwd=tmp_path))
    assert "is 300 bytes: allowed at most" in line, line
    line = usage_error(run("exercise", "start", "schlick-fresnel", "no/work", cwd=tmp_path))
    assert "'no' of 'no/work' does not exist" in line, line
    assert list(tmp_path.iterdir()) == []  # no temporary left


def test_a_teachers_own_toml_file_is_an_exercise(tmp_path):
    text = ex_mod.find("schlick-fresnel").text.replace('title = "Schlick\'s Fresnel"',
                                                       'title = "Fresnel, my way"')
    (tmp_path / "my-fresnel.toml").write_text(text, encoding="utf-8")
    r = run("exercise", "start", "my-fresnel.toml", "work", cwd=tmp_path)
    assert r.returncode == 0, r.stderr
    assert "exercise my-fresnel: Fresnel, my way" in r.stdout
    r = run("exercise", "check", "work", cwd=tmp_path)  # the stub: fails, nothing matched
    assert r.returncode == 1 and "exercise my-fresnel: FAIL" in r.stdout
    assert "likely mistake" not in r.stdout
    bad = text.replace('function = "SchlickFresnel"', 'function = "Schlick"')
    (tmp_path / "bad.toml").write_text(bad, encoding="utf-8")
    line = usage_error(run("exercise", "start", "bad.toml", "other", cwd=tmp_path))
    assert "defines no function 'Schlick'" in line


def test_every_exercises_stub_is_neutral_and_compiles():
    """The stub of each return type (no GL: the text the copy gets)."""
    for ex in ex_mod.all_exercises():
        text = (ex_mod.DEFAULT_SHADER_ROOT / ex.file).read_text(encoding="utf-8")
        out = ex_mod.replace_bodies(text, ex.function, ex_mod.stub_body(ex, Path("d")))
        spans = ex_mod.function_spans(out, ex.function)
        assert len(spans) == len(ex_mod.function_spans(text, ex.function)) >= 1
        for ret, start, end in spans:
            body = out[start:end]
            assert "natura exercise check d" in body
            assert ret == "void" or re.search(r"return [^;]+;", body), body
    assert np.isfinite(1.0)
