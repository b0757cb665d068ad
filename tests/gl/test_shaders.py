"""The shader library (DESIGN.md "Shader library"; issue 2 items 3 and 9).

Each test builds its own small shader root under ``tmp_path`` and compiles it on the suite's
EGL context, so they check the library's rules (includes, defines, error lines, live reload)
and not the project's shaders (those compile through the CLI: tests/cli/test_shaders.py).
"""

from __future__ import annotations

import os
import textwrap
import time
from pathlib import Path

import moderngl
import numpy as np
import pytest

from app import DEFAULT_SHADER_ROOT
from app.errors import ShaderCompileError
from app.gpu.shaders import ShaderLibrary

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
    # hidden by fx/shadow.glsl
    write(r, "common/shadow.glsl", "float shadowValue() { return 0.1; }\n")
    write(r, "common/once.glsl", "float onceValue() { return 0.125; }\n")
    write(r, "fx/shadow.glsl", "float shadowValue() { return 0.9; }\n")
    # NOT the one deep/deep.glsl means
    write(r, "fx/leaf.glsl", "float leafValue() { return 0.7; }\n")
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
    # deep/deep.glsl's "leaf.glsl" is fx/deep/leaf.glsl (relative to deep.glsl, not to the main
    # file).
    np.testing.assert_allclose(render_pixel(lib.ctx, prog), [0.9, 0.5, 0.3, 1.0], atol=1e-6)
    files = {p.relative_to(root.resolve()).as_posix() for p in prog.files}
    assert files == {"common/fullscreen.vert", "fx/resolve.frag", "fx/shadow.glsl",
                     "common/value.glsl", "fx/deep/deep.glsl", "fx/deep/leaf.glsl"}


def test_each_file_is_included_once(lib, root):
    write(root, "fx/twice.glsl",
          '#include "once.glsl"\nfloat twiceValue() { return 2.0 * onceValue(); }\n')
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
    write(root, "fx/outer.frag",
          '#version 330 core\n#include "inner.glsl"\nout vec4 c;\nvoid main() { c = vec4(1.0); }\n')
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
    # "2" would be an int: vec4(int, ...) is fine, but the text must be a float literal
    prog = program(lib, "fx/define", defines={"VALUE": 2.0})
    assert render_pixel(lib.ctx, prog)[0] == pytest.approx(2.0)
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
    write(root, "fx/deep/middle.glsl",
          '// middle\n#include "bad_leaf.glsl"\nfloat middle() { return badLeaf(); }\n')
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
    vert = write(root, "fx/bad.vert",
                 FULLSCREEN_VERT.replace("vUV = p;", "vUV = p;\n    undefined_call();"))
    write(root, "fx/bad.frag", '#version 330 core\n#include "value.glsl"\nout vec4 c;\n'
                               "void main() { c = vec4(commonValue()); }\n")
    with pytest.raises(ShaderCompileError) as info:
        lib.program("fx/bad")
    assert {(e.file, e.line) for e in info.value.errors} == {(lib.display(vert),
                                                              line_of(vert, "undefined_call"))}


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
    save_like_editor(main, "#version 330 core\nout vec4 fragColor;\n"
                           "void main() { fragColor = vec4(0.5); }\n")
    assert lib.poll() == [prog] and prog.errors == []
    prog.set("uUsed", 0.1)
    assert "uUsed" not in prog
    assert render_pixel(lib.ctx, prog)[0] == pytest.approx(0.5)
