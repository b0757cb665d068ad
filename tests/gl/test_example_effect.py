"""docs/architecture.md walks a newcomer through adding an effect ("Adding an effect"). The
walk-through's files live in tests/example/ so that this module can check, first, that the
document shows exactly those files and, second, that the effect they make renders and does what
its test says — mounted the way a real effect is: its GLSL folder beside the others under the
shader root, its scene in the scene registry."""

from __future__ import annotations

import re

import pytest

from app import DEFAULT_SHADER_ROOT, PROJECT_ROOT
from app.scenes import SCENES
from tests.example.check_vignette import (
    test_vignette_darkens_each_pixel_by_cos4_of_its_angle as walkthrough_test,
)
from tests.example.scene import VignetteScene

EXAMPLE = PROJECT_ROOT / "tests" / "example"
DOC = PROJECT_ROOT / "docs" / "architecture.md"
#: where each file of the walk-through lives in a project (as the document names it) → here
FILES = {
    "glsl/vignette/vignette.frag": EXAMPLE / "glsl" / "vignette" / "vignette.frag",
    "app/effects/vignette/effect.py": EXAMPLE / "vignette" / "effect.py",
    "app/effects/vignette/__init__.py": EXAMPLE / "vignette" / "__init__.py",
    "app/scenes/vignette.py": EXAMPLE / "scene.py",
    "tests/gl/test_vignette.py": EXAMPLE / "check_vignette.py",
}
#: the one line that differs: where the example is imported from
IMPORTS = {"tests.example.vignette": "app.effects.vignette"}
BLOCK = re.compile(r"^```\w+ file=(\S+)\n(.*?)^```", re.M | re.S)


def document_blocks() -> dict[str, str]:
    return {path: code for path, code in BLOCK.findall(DOC.read_text(encoding="utf-8"))}


def as_in_a_project(text: str) -> str:
    for here, there in IMPORTS.items():
        text = text.replace(here, there)
    return re.sub(r'^"""(.*?)\(in your own project: [^)]*\)', r'"""\1', text, count=1, flags=re.S)


def test_the_document_shows_every_file_of_the_example():
    blocks = document_blocks()
    assert set(blocks) == set(FILES), "docs/architecture.md and tests/example/ name different files"
    for path, here in FILES.items():
        assert blocks[path] == as_in_a_project(here.read_text(encoding="utf-8")), (
            f"docs/architecture.md's {path} is not tests/example/{here.relative_to(EXAMPLE)}: "
            "python tools/sync_architecture_example.py copies the example into the document")


@pytest.fixture
def mounted(tmp_path, monkeypatch):
    """A shader root holding glsl/ and the example's folder; the example's scene registered."""
    root = tmp_path / "glsl"
    root.mkdir()
    for entry in DEFAULT_SHADER_ROOT.iterdir():
        (root / entry.name).symlink_to(entry)
    (root / "vignette").symlink_to(EXAMPLE / "glsl" / "vignette")
    monkeypatch.setenv("NATURA_SHADERS", str(root))
    monkeypatch.setitem(SCENES, "vignette", VignetteScene)
    return root


def test_the_example_effect_renders_as_its_test_says(mounted, render):
    walkthrough_test(render)


def test_the_example_effect_is_an_ordinary_effect(mounted):
    from app.runtime import scene_params

    params = scene_params("vignette")
    spec = params.spec("vignette.amount")  # the shader's @param annotation, without Python
    assert (spec.default, spec.lo, spec.hi) == (1.0, 0.0, 1.0)
    VignetteScene.check_slots()  # its required slot (the image) is produced by the scene
