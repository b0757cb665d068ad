"""Natura: natural effects from five graphics theses, rendered with moderngl.

The package layout is described in docs/architecture.md: ``gpu`` (contexts, shader library,
targets, timing), ``effects`` (one package per effect), ``sim`` (numpy-only simulation),
``render`` (helpers shared by the effects), ``scenes``, ``ui`` and ``bench``.
"""

from pathlib import Path

__version__ = "0.1.0"

#: Repository root when installed editable (``pip install -e .``), as the README does.
PROJECT_ROOT = Path(__file__).resolve().parent.parent
#: Default GLSL folder; ``--shaders DIR`` or ``NATURA_SHADERS`` points elsewhere.
DEFAULT_SHADER_ROOT = PROJECT_ROOT / "glsl"
RESOURCES = PROJECT_ROOT / "resources"
