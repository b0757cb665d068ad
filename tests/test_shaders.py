"""The shader library (DESIGN.md "Shader library"; issue 2 items 3 and 9).

Most tests build their own small shader root under ``tmp_path`` and compile it on a standalone
EGL context, so they check the library's rules (includes, defines, error lines, live reload)
and not the project's shaders. The last tests compile every real program through the CLI.
"""

from __future__ import annotations

import os
import subprocess
import sys
import textwrap
import time
from pathlib import Path

import moderngl
import numpy as np
import pytest

from app import DEFAULT_SHADER_ROOT, PROJECT_ROOT
from app.errors import ShaderCompileError, UsageError
from app.gpu.shaders import SHADER_ENV, ShaderLibrary, resolve_shader_root

FULLSCREEN_VERT = """\
#version 330 core
out vec2 vUV;
void main() {
    vec2 p = vec2((gl_VertexID << 1) & 2, gl_VertexID & 2);
    vUV = p;
    gl_Position = vec4(p * 2.0 - 1.0, 0.0, 1.0);
}
"""


@pytest.fixture
def gl(gl_ctx):
    """The suite's one EGL context (tests/conftest.py): a second standalone context would
    become current and leave the shared one unusable for later test modules."""
    return gl_ctx


def write(root: Path, rel: str, text: str) -> Path:
    path = root / rel
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(textwrap.dedent(text), encoding="utf-8")
    return path


def save_like_editor(path: Path, text: str) -> None:
    """Save the way many editors do: write a temporary file, then rename it over the original.
    The new file gets a modification time clearly later than the old one's."""
    old_ns = path.stat().st_mtime_ns if path.exists() else 0
    tmp = path.with_name(f".{path.name}.swp")
    tmp.write_text(textwrap.dedent(text), encoding="utf-8")
    ns = max(time.time_ns(), old_ns + 50_000_000)
    os.utime(tmp, ns=(ns, ns))
    os.replace(tmp, path)


def line_of(path: Path, needle: str) -> int:
    """1-based number of the only line of ``path`` containing ``needle``."""
    hits = [i for i, line in enumerate(path.read_text().splitlines(), 1) if needle in line]
    assert len(hits) == 1, (needle, hits)
    return hits[0]


def render_pixel(gl: moderngl.Context, prog) -> np.ndarray:
    """Draw a full-screen triangle with ``prog`` into a 1×1 float target; return RGBA."""
    tex = gl.texture((1, 1), 4, dtype="f4")
    fbo = gl.framebuffer(color_attachments=[tex])
    try:
        fbo.use()
        fbo.clear(0.0, 0.0, 0.0, 0.0)
        prog.vao().render(moderngl.TRIANGLES, vertices=3)
        return np.frombuffer(fbo.read(components=4, dtype="f4"), dtype=np.float32).copy()
    finally:
        fbo.release()
        tex.release()


@pytest.fixture
def root(tmp_path) -> Path:
    """A small shader root: ``common/`` plus an effect folder ``fx/``."""
    r = tmp_path / "glsl"
    write(r, "common/fullscreen.vert", FULLSCREEN_VERT)
    write(r, "common/value.glsl", """\
        // only in common/
        float commonValue() {
            return 0.5;
        }
        """)
    write(r, "common/shadow.glsl", "float shadowValue() { return 0.1; }\n")  # hidden by fx/shadow.glsl
    write(r, "common/once.glsl", "float onceValue() { return 0.125; }\n")
    write(r, "fx/shadow.glsl", "float shadowValue() { return 0.9; }\n")
    write(r, "fx/leaf.glsl", "float leafValue() { return 0.7; }\n")  # NOT the one deep/deep.glsl means
    write(r, "fx/deep/leaf.glsl", "float leafValue() { return 0.3; }\n")
    write(r, "fx/deep/deep.glsl", '#include "leaf.glsl"\n')
    return r


@pytest.fixture
def lib(gl, root) -> ShaderLibrary:
    library = ShaderLibrary(gl, root)
    yield library
    library.release()


def program(lib: ShaderLibrary, name: str, **kw):
    return lib.program(name, vert="common/fullscreen.vert", frag=f"{name}.frag", **kw)


# ---- includes ----------------------------------------------------------------------------------

def test_include_relative_to_including_file_then_common(lib, root):
    write(root, "fx/resolve.frag", """\
        #version 330 core
        #include "shadow.glsl"
        #include "value.glsl"
        #include "deep/deep.glsl"
        out vec4 fragColor;
        void main() { fragColor = vec4(shadowValue(), commonValue(), leafValue(), 1.0); }
        """)
    prog = program(lib, "fx/resolve")
    # fx/shadow.glsl beats common/shadow.glsl; value.glsl only exists in common/;
    # deep/deep.glsl's "leaf.glsl" is fx/deep/leaf.glsl (relative to deep.glsl, not to the main file).
    np.testing.assert_allclose(render_pixel(lib.ctx, prog), [0.9, 0.5, 0.3, 1.0], atol=1e-6)
    files = {p.relative_to(root.resolve()).as_posix() for p in prog.files}
    assert files == {"common/fullscreen.vert", "fx/resolve.frag", "fx/shadow.glsl", "common/value.glsl",
                     "fx/deep/deep.glsl", "fx/deep/leaf.glsl"}


def test_each_file_is_included_once(lib, root):
    write(root, "fx/twice.glsl", '#include "once.glsl"\nfloat twiceValue() { return 2.0 * onceValue(); }\n')
    write(root, "fx/once.frag", """\
        #version 330 core
        #include "once.glsl"
        #include "twice.glsl"
        #include "once.glsl"
        out vec4 fragColor;
        void main() { fragColor = vec4(onceValue(), twiceValue(), 0.0, 1.0); }
        """)
    # Expanded twice, onceValue() would be a redefinition and the compile would fail.
    prog = program(lib, "fx/once")
    np.testing.assert_allclose(render_pixel(lib.ctx, prog), [0.125, 0.25, 0.0, 1.0], atol=1e-6)
    text = lib.preprocess(root / "fx/once.frag").text
    assert text.count("float onceValue()") == 1


def test_missing_include_names_the_including_file_and_line(lib, root):
    main = write(root, "fx/missing.frag", """\
        #version 330 core
        // a comment
        #include "nope.glsl"
        out vec4 fragColor;
        void main() { fragColor = vec4(1.0); }
        """)
    with pytest.raises(ShaderCompileError) as info:
        program(lib, "fx/missing")
    err = info.value.errors[0]
    assert (err.file, err.line) == (lib.display(main), 3)
    assert "nope.glsl" in err.message
    assert str(info.value).startswith(f"{lib.display(main)}:3: ")
    assert info.value.exit_code == 1


def test_missing_include_inside_an_included_file_names_that_file(lib, root):
    inner = write(root, "fx/inner.glsl", "// inner\n\n#include \"gone.glsl\"\n")
    write(root, "fx/outer.frag", '#version 330 core\n#include "inner.glsl"\nout vec4 c;\nvoid main() { c = vec4(1.0); }\n')
    with pytest.raises(ShaderCompileError) as info:
        program(lib, "fx/outer")
    err = info.value.errors[0]
    assert (err.file, err.line) == (lib.display(inner), 3)
    assert "gone.glsl" in err.message


# ---- defines -----------------------------------------------------------------------------------

DEFINE_FRAG = """\
    // defines must land after #version, even with comments before it
    #version 330 core
    #include "defined.glsl"
    #ifndef VALUE
    #define VALUE 0.25
    #endif
    out vec4 fragColor;
    void main() {
    #if FLAG
        fragColor = vec4(VALUE, 1.0, definedValue(), 1.0);
    #else
        fragColor = vec4(VALUE, 0.0, definedValue(), 1.0);
    #endif
    }
    """


def test_defines_are_injected_after_version(lib, root):
    write(root, "fx/defined.glsl", """\
        #ifndef SCALE
        #define SCALE 1
        #endif
        float definedValue() { return 0.0625 * float(SCALE); }
        """)
    write(root, "fx/define.frag", DEFINE_FRAG)
    plain = program(lib, "fx/define")
    defined = program(lib, "fx/define", defines={"VALUE": 0.75, "FLAG": True, "SCALE": 3})
    assert plain is not defined
    np.testing.assert_allclose(render_pixel(lib.ctx, plain), [0.25, 0.0, 0.0625, 1.0], atol=1e-6)
    np.testing.assert_allclose(render_pixel(lib.ctx, defined), [0.75, 1.0, 0.1875, 1.0], atol=1e-6)

    lines = lib.preprocess(root / "fx/define.frag", {"VALUE": 0.75, "FLAG": True}).text.splitlines()
    version = next(i for i, line in enumerate(lines) if line.startswith("#version"))
    assert lines[version + 1: version + 3] == ["#define VALUE 0.75", "#define FLAG 1"]
    assert not any(line.startswith("#define VALUE") for line in lines[:version])


def test_a_float_define_stays_a_float(lib, root):
    write(root, "fx/defined.glsl", "float definedValue() { return 0.0; }\n")
    write(root, "fx/define.frag", DEFINE_FRAG)
    prog = program(lib, "fx/define", defines={"VALUE": 2.0})  # "2" would be an int: vec4(int, ...) is fine,
    assert render_pixel(lib.ctx, prog)[0] == pytest.approx(2.0)  # but the text must be a float literal
    assert "#define VALUE 2.0" in lib.preprocess(root / "fx/define.frag", {"VALUE": 2.0}).text


# ---- error lines -------------------------------------------------------------------------------

BROKEN_STATEMENTS = {
    "undeclared": "return undeclared_thing;",
    "syntax": "return 1.0 +;",
    "type": "int i = vec3(1.0); return 0.0;",
}


@pytest.mark.parametrize("kind", sorted(BROKEN_STATEMENTS))
def test_error_in_an_included_file_reports_that_file_and_line(lib, root, kind):
    broken = write(root, "fx/broken.glsl", f"""\
        // line 1
        // line 2
        float brokenValue() {{
            {BROKEN_STATEMENTS[kind]}
        }}
        """)
    main = write(root, "fx/uses_broken.frag", """\
        #version 330 core
        #include "value.glsl"
        #include "broken.glsl"
        out vec4 fragColor;
        void main() { fragColor = vec4(brokenValue() + commonValue()); }
        """)
    with pytest.raises(ShaderCompileError) as info:
        program(lib, "fx/uses_broken")
    where = {(e.file, e.line) for e in info.value.errors}
    assert where == {(lib.display(broken), 4)}, info.value.errors
    assert lib.display(main) != lib.display(broken)
    assert f"{lib.display(broken)}:4: " in str(info.value)


def test_error_in_a_nested_include_reports_the_innermost_file(lib, root):
    inner = write(root, "fx/deep/bad_leaf.glsl", "\n\nfloat badLeaf() { return missing_name; }\n")
    write(root, "fx/deep/middle.glsl", '// middle\n#include "bad_leaf.glsl"\nfloat middle() { return badLeaf(); }\n')
    write(root, "fx/nested.frag", '#version 330 core\n#include "deep/middle.glsl"\nout vec4 c;\n'
                                  "void main() { c = vec4(middle()); }\n")
    with pytest.raises(ShaderCompileError) as info:
        program(lib, "fx/nested")
    assert {(e.file, e.line) for e in info.value.errors} == {(lib.display(inner), 3)}


def test_error_in_the_main_file_after_includes_reports_its_own_line(lib, root):
    main = write(root, "fx/bad_main.frag", """\
        #version 330 core
        #include "value.glsl"
        #include "shadow.glsl"
        out vec4 fragColor;
        void main() {
            fragColor = vec4(commonValue() + shadowValue() + missing_var);
        }
        """)
    with pytest.raises(ShaderCompileError) as info:
        program(lib, "fx/bad_main")
    assert {(e.file, e.line) for e in info.value.errors} == {(lib.display(main), 6)}
    assert "missing_var" in info.value.errors[0].message


def test_error_in_the_vertex_stage_names_the_vertex_file(lib, root):
    vert = write(root, "fx/bad.vert", FULLSCREEN_VERT.replace("vUV = p;", "vUV = p;\n    undefined_call();"))
    write(root, "fx/bad.frag", '#version 330 core\n#include "value.glsl"\nout vec4 c;\n'
                               "void main() { c = vec4(commonValue()); }\n")
    with pytest.raises(ShaderCompileError) as info:
        lib.program("fx/bad")
    assert {(e.file, e.line) for e in info.value.errors} == {(lib.display(vert), line_of(vert, "undefined_call"))}


def test_project_shaders_are_named_glsl_relative(gl):
    lib = ShaderLibrary(gl, DEFAULT_SHADER_ROOT)
    assert lib.display(DEFAULT_SHADER_ROOT / "sky" / "sky.frag") == "glsl/sky/sky.frag"


# ---- live reload -------------------------------------------------------------------------------

LIVE_FRAG = """\
    #version 330 core
    #include "live_value.glsl"
    out vec4 fragColor;
    void main() {
        fragColor = vec4(liveValue() + {offset}, 0.0, 0.0, 1.0);
    }
    """


def test_live_reload_good_broken_fixed(lib, root):
    main = write(root, "fx/live.frag", LIVE_FRAG.replace("{offset}", "0.0"))
    write(root, "fx/live_value.glsl", "float liveValue() { return 0.25; }\n")
    prog = program(lib, "fx/live")
    reloads = []
    prog.on_reload.append(reloads.append)
    good = prog.program
    assert render_pixel(lib.ctx, prog)[0] == pytest.approx(0.25)
    assert lib.poll() == []  # nothing changed: nothing recompiled

    # good → broken: the error names file:line, the last good program keeps rendering
    broken_text = LIVE_FRAG.replace("{offset}", "0.0 + oops_undeclared")
    save_like_editor(main, broken_text)
    assert lib.poll() == [prog]
    assert {(e.file, e.line) for e in prog.errors} == {(lib.display(main), 5)}
    assert any("oops_undeclared" in e.message for e in prog.errors)
    assert lib.errors() == prog.errors
    assert prog.program is good and prog.generation == 1 and reloads == []
    assert render_pixel(lib.ctx, prog)[0] == pytest.approx(0.25)
    assert main.read_text() == textwrap.dedent(broken_text)  # the user's file is never edited
    assert lib.poll() == []  # the same broken file is not recompiled on every poll

    # broken → fixed: recompiled, errors cleared, the new value renders
    save_like_editor(main, LIVE_FRAG.replace("{offset}", "0.5"))
    assert lib.poll() == [prog]
    assert prog.errors == [] and lib.errors() == []
    assert prog.generation == 2 and reloads == [prog]
    assert render_pixel(lib.ctx, prog)[0] == pytest.approx(0.75)


def test_change_in_an_included_file_reloads_the_including_program(lib, root):
    write(root, "fx/live.frag", LIVE_FRAG.replace("{offset}", "0.0"))
    value = write(root, "fx/live_value.glsl", "float liveValue() { return 0.25; }\n")
    write(root, "fx/other.frag", '#version 330 core\n#include "value.glsl"\nout vec4 c;\n'
                                 "void main() { c = vec4(commonValue()); }\n")
    prog = program(lib, "fx/live")
    other = program(lib, "fx/other")
    assert render_pixel(lib.ctx, prog)[0] == pytest.approx(0.25)

    save_like_editor(value, "float liveValue() { return 0.125; }\n")
    assert lib.poll() == [prog]  # the program that does not include it is left alone
    assert render_pixel(lib.ctx, prog)[0] == pytest.approx(0.125)
    assert other.generation == 1

    # an error in the included file is reported there, and the last good program stays
    save_like_editor(value, "float liveValue() {\n    return 0.5 * nothing_here;\n}\n")
    assert lib.poll() == [prog]
    assert {(e.file, e.line) for e in prog.errors} == {(lib.display(value), 2)}
    assert render_pixel(lib.ctx, prog)[0] == pytest.approx(0.125)


def test_reload_survives_a_file_missing_in_the_middle_of_a_save(lib, root):
    main = write(root, "fx/live.frag", LIVE_FRAG.replace("{offset}", "0.0"))
    write(root, "fx/live_value.glsl", "float liveValue() { return 0.25; }\n")
    prog = program(lib, "fx/live")
    backup = main.with_name("live.frag~")
    os.replace(main, backup)  # some editors move the original away before writing the new one
    assert lib.poll() == []
    assert prog.errors == [] and render_pixel(lib.ctx, prog)[0] == pytest.approx(0.25)
    save_like_editor(main, LIVE_FRAG.replace("{offset}", "0.25"))
    assert lib.poll() == [prog]
    assert render_pixel(lib.ctx, prog)[0] == pytest.approx(0.5)


def test_uniforms_removed_by_the_compiler_are_tolerated(lib, root):
    main = write(root, "fx/uniforms.frag", """\
        #version 330 core
        uniform float uUsed;
        uniform float uUnused;  // declared, never read: the compiler drops it
        out vec4 fragColor;
        void main() { fragColor = vec4(uUsed, 0.0, 0.0, 1.0); }
        """)
    prog = program(lib, "fx/uniforms")
    assert "uUsed" in prog and "uUnused" not in prog
    prog.set("uUnused", 1.0)
    prog.set("uNeverDeclared", (1.0, 2.0, 3.0))
    prog.set_many({"uUsed": 0.375, "uUnused": 2.0})
    assert render_pixel(lib.ctx, prog)[0] == pytest.approx(0.375)

    # an edit that removes a uniform: setting it afterwards is still fine
    save_like_editor(main, "#version 330 core\nout vec4 fragColor;\nvoid main() { fragColor = vec4(0.5); }\n")
    assert lib.poll() == [prog] and prog.errors == []
    prog.set("uUsed", 0.1)
    assert "uUsed" not in prog
    assert render_pixel(lib.ctx, prog)[0] == pytest.approx(0.5)


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


# ---- the project's own shaders, through the CLI ------------------------------------------------

def natura(*args: str, cwd: Path, env: dict | None = None) -> subprocess.CompletedProcess:
    env = dict(os.environ if env is None else env)
    env.pop(SHADER_ENV, None)
    env["PYTHONPATH"] = os.pathsep.join(filter(None, [str(PROJECT_ROOT), env.get("PYTHONPATH")]))
    cmd = [sys.executable, "-c", "from app.cli import main; raise SystemExit(main())", *args]
    return subprocess.run(cmd, cwd=cwd, env=env, capture_output=True, text=True, timeout=120)


def test_every_project_program_compiles(tmp_path):
    r = natura("shaders", "check", cwd=tmp_path)
    assert r.returncode == 0, r.stdout + r.stderr
    for name in ("sky/sky", "sky/sky_face", "probe/mirror_ball", "common/constant"):
        assert any(line.split()[:2] in (["ok", name], ["skip", f"{name}:"]) for line in r.stdout.splitlines()), r.stdout
    assert "ok" in r.stdout
    assert not any(":" in line.split()[0] for line in r.stdout.splitlines() if line.strip())  # no file:line errors


def test_a_broken_copy_fails_the_check_with_file_and_line(tmp_path):
    copy = tmp_path / "my-shaders"
    r = natura("shaders", "copy", str(copy), cwd=tmp_path)
    assert r.returncode == 0, r.stderr
    radiance = copy / "sky" / "sky_radiance.glsl"
    original = (DEFAULT_SHADER_ROOT / "sky" / "sky_radiance.glsl").read_text()
    assert radiance.read_text() == original
    bad_line = len(original.splitlines()) + 1
    with radiance.open("a") as f:
        f.write("float nataraBroken() { return not_declared_anywhere; }\n")

    r = natura("shaders", "check", "--shaders", str(copy), cwd=tmp_path)
    assert r.returncode == 1, r.stdout + r.stderr
    errors = [line for line in r.stdout.splitlines() if f"sky_radiance.glsl:{bad_line}:" in line]
    assert errors, r.stdout
    assert all(line.startswith("my-shaders/sky/sky_radiance.glsl:") for line in errors)
    assert any("not_declared_anywhere" in line for line in errors)
    assert "ok   probe/mirror_ball" in r.stdout  # programs that don't include the file still compile

    # the default shaders are untouched and still pass
    assert (DEFAULT_SHADER_ROOT / "sky" / "sky_radiance.glsl").read_text() == original


def test_shaders_copy_never_overwrites(tmp_path):
    dest = tmp_path / "exists"
    dest.mkdir()
    (dest / "keep.txt").write_text("mine")
    r = natura("shaders", "copy", str(dest), cwd=tmp_path)
    assert r.returncode == 2
    assert len(r.stderr.strip().splitlines()) == 1 and "already exists" in r.stderr
    assert sorted(p.name for p in dest.iterdir()) == ["keep.txt"]
