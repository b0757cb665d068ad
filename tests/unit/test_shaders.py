"""The shader library (DESIGN.md "Shader library"; issue 2 item 3) without a context: where
the shaders come from (--shaders, $NATURA_SHADERS, the project's glsl/).
"""

from __future__ import annotations

import pytest

from app import DEFAULT_SHADER_ROOT
from app.errors import UsageError
from app.gpu.shaders import SHADER_ENV, resolve_shader_root

# ---- where the shaders come from ---------------------------------------------------------------

def test_resolve_shader_root(tmp_path, monkeypatch):
    arg_dir, env_dir = tmp_path / "from_arg", tmp_path / "from_env"
    arg_dir.mkdir()
    env_dir.mkdir()
    monkeypatch.delenv(SHADER_ENV, raising=False)
    assert resolve_shader_root(None) == DEFAULT_SHADER_ROOT
    assert resolve_shader_root(str(arg_dir)) == arg_dir.resolve()
    monkeypatch.setenv(SHADER_ENV, str(env_dir))
    assert resolve_shader_root(None) == env_dir.resolve()
    assert resolve_shader_root(arg_dir) == arg_dir.resolve()  # --shaders beats the variable


def test_resolve_shader_root_rejects_a_non_directory(tmp_path, monkeypatch):
    monkeypatch.delenv(SHADER_ENV, raising=False)
    a_file = tmp_path / "not_a_dir.glsl"
    a_file.write_text("")
    with pytest.raises(UsageError) as info:
        resolve_shader_root(str(a_file))
    assert "--shaders" in str(info.value) and str(a_file) in str(info.value)
    assert info.value.exit_code == 2
    monkeypatch.setenv(SHADER_ENV, str(tmp_path / "missing"))
    with pytest.raises(UsageError) as info:
        resolve_shader_root(None)
    assert SHADER_ENV in str(info.value) and "missing" in str(info.value)
