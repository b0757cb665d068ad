"""The import layers of docs/architecture.md, enforced: a module imports only from its own layer
and the layers below it, ``app/sim`` never imports GL, and no effect imports another effect or
reaches into the scene.

    base     app, app.errors, app.params, app.colour
    gpu      app.gpu            (base)
    sim      app.sim            (base; numpy only: no moderngl, no window or UI library)
    render   app.frame, app.render, app.bakes   (base, gpu, sim)
    effects  app.effects        (… render; each effect package only itself and effects.base)
    scenes   app.scenes         (… effects)
    runtime  app.runtime, app.imageio, app.teach   (… scenes)
    ui       app.ui             (… runtime)
    bench    app.bench          (… runtime)
    cli      app.cli            (everything)
"""

from __future__ import annotations

import ast
from pathlib import Path

from app import PROJECT_ROOT

APP = PROJECT_ROOT / "app"

LAYERS = ("base", "gpu", "sim", "render", "effects", "scenes", "runtime", "ui", "bench", "cli")
#: layer → the layers it may import (besides itself)
ALLOWED = {
    "base": set(),
    "gpu": {"base"},
    "sim": {"base"},
    "render": {"base", "gpu", "sim"},
    "effects": {"base", "gpu", "sim", "render"},
    "scenes": {"base", "gpu", "sim", "render", "effects"},
    "runtime": {"base", "gpu", "sim", "render", "effects", "scenes"},
    "ui": {"base", "gpu", "sim", "render", "effects", "scenes", "runtime"},
    "bench": {"base", "gpu", "sim", "render", "effects", "scenes", "runtime"},
    "cli": set(LAYERS) - {"cli"},
}
#: third-party packages that mean GL or a window: never in app/sim
GL_PACKAGES = {"moderngl", "moderngl_window", "glcontext", "imgui_bundle", "pyglet", "OpenGL"}


def layer_of(module: str) -> str:
    parts = module.split(".")
    if parts[0] != "app":
        raise ValueError(module)
    if len(parts) == 1 or parts[1] in ("errors", "params", "colour"):
        return "base"
    head = parts[1]
    if head in ("gpu", "sim", "effects", "scenes", "ui", "bench", "cli"):
        return head
    if head in ("frame", "render", "bakes"):
        return "render"
    if head in ("runtime", "imageio", "teach"):
        return "runtime"
    raise ValueError(f"module {module} has no layer: add it to tests/unit/test_layers.py and "
                     "docs/architecture.md")


def module_name(path: Path) -> str:
    rel = path.relative_to(PROJECT_ROOT).with_suffix("")
    parts = list(rel.parts)
    if parts[-1] == "__init__":
        parts.pop()
    return ".".join(parts)


def imports_of(path: Path) -> list[tuple[int, str]]:
    """(line, absolute module) of every import in the file, at any depth (lazy imports count)."""
    tree = ast.parse(path.read_text(encoding="utf-8"), str(path))
    package = module_name(path)
    if path.name != "__init__.py":
        package = package.rpartition(".")[0]
    out = []
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            out.extend((node.lineno, alias.name) for alias in node.names)
        elif isinstance(node, ast.ImportFrom):
            if node.level:
                base = package.split(".")
                base = base[: len(base) - (node.level - 1)]
                mod = ".".join(base + ([node.module] if node.module else []))
            else:
                mod = node.module or ""
            out.append((node.lineno, mod))
            if node.module is None or node.level:  # from . import x: x may be a module
                out.extend((node.lineno, f"{mod}.{alias.name}") for alias in node.names)
    return out


def app_files() -> list[Path]:
    return sorted(p for p in APP.rglob("*.py") if "__pycache__" not in p.parts)


def effect_package(module: str) -> str | None:
    parts = module.split(".")
    if len(parts) >= 3 and parts[:2] == ["app", "effects"] and parts[2] != "base":
        return parts[2]
    return None


def existing(module: str) -> bool:
    rel = Path(*module.split("."))
    return ((PROJECT_ROOT / rel).with_suffix(".py").is_file()
            or (PROJECT_ROOT / rel / "__init__.py").is_file())


def test_every_module_has_a_layer():
    for path in app_files():
        layer_of(module_name(path))


def test_no_module_imports_a_higher_layer():
    bad = []
    for path in app_files():
        mod = module_name(path)
        here = layer_of(mod)
        for line, target in imports_of(path):
            if target.split(".")[0] != "app" or not existing(target):
                continue
            there = layer_of(target)
            if there != here and there not in ALLOWED[here]:
                bad.append(f"{path.relative_to(PROJECT_ROOT)}:{line}: {mod} ({here}) imports "
                           f"{target} ({there})")
    assert not bad, "imports against the layers:\n" + "\n".join(bad)


def test_sim_never_imports_gl():
    bad = []
    for path in (APP / "sim").rglob("*.py"):
        for line, target in imports_of(path):
            if target.split(".")[0] in GL_PACKAGES:
                bad.append(f"{path.relative_to(PROJECT_ROOT)}:{line}: imports {target}")
    assert not bad, "app/sim must stay numpy-only:\n" + "\n".join(bad)


def test_no_effect_imports_another_effect():
    bad = []
    for path in (APP / "effects").rglob("*.py"):
        mine = effect_package(module_name(path))
        for line, target in imports_of(path):
            theirs = effect_package(target)
            if theirs is not None and theirs != mine:
                bad.append(f"{path.relative_to(PROJECT_ROOT)}:{line}: effect {mine!r} imports "
                           f"effect {theirs!r}")
    assert not bad, "effects meet through frame slots, never by import:\n" + "\n".join(bad)


def test_no_effect_reaches_into_the_scene():
    """Effects get nothing from the scene: no ``self.scene``, no ``effect(name)`` lookups."""
    bad = []
    for path in (APP / "effects").rglob("*.py"):
        for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
            if not isinstance(node, ast.Attribute):
                continue
            on_self = isinstance(node.value, ast.Name) and node.value.id == "self"
            lookup = node.attr in ("has_effect", "effect", "active_instances")
            if (node.attr == "scene" and on_self) or lookup:
                bad.append(f"{path.relative_to(PROJECT_ROOT)}:{node.lineno}: .{node.attr}")
    assert not bad, "\n".join(bad)


def test_the_walker_sees_relative_and_lazy_imports():
    found = {mod for _, mod in imports_of(APP / "effects" / "ocean" / "sea.py")}
    # the FFT simulation is imported lazily, inside a method
    assert {"app.sim.ocean", "app.effects.ocean.params", "app.effects.ocean.fft"} <= found
