"""The shader library (DESIGN.md "Shader library"; issue 2 items 3 and 9).

Each test builds its own small shader root under ``tmp_path`` and compiles it on the suite's
EGL context, so they check the library's rules (includes, defines, error lines, live reload)
and not the project's shaders (those compile through the CLI: tests/cli/test_shaders.py). The
live-reload cases a running window must survive (a file replaced by a folder or a pipe, bad
bytes, deleted and recreated files, link errors, uniforms whose type changed, broken ``@param``
annotations) each have a test here; tests/stability/test_fuzz_shaders.py mixes them at random.
"""

from __future__ import annotations

import os
import textwrap
import time
from contextlib import contextmanager
from pathlib import Path

import moderngl
import numpy as np
import pytest

from app import DEFAULT_SHADER_ROOT
from app.errors import ShaderCompileError
from app.gpu.shaders import MAX_SOURCE_BYTES, ShaderLibrary
from tests.helpers.hang import finishes

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


# ---- live reload hardened: what a running window must survive ----------------------------------

VALUE_FRAG = """\
    #version 330 core
    #include "live_value.glsl"
    uniform float uScale;
    out vec4 fragColor;
    void main() {
        fragColor = vec4(liveValue() * uScale, 0.0, 0.0, 1.0);
    }
    """


@pytest.fixture
def live(lib, root):
    """A program ``fx/live`` = fullscreen.vert + fx/live.frag including fx/live_value.glsl,
    rendering 0.25 × uScale (uScale = 1)."""
    main = write(root, "fx/live.frag", VALUE_FRAG)
    value = write(root, "fx/live_value.glsl", "float liveValue() { return 0.25; }\n")
    prog = program(lib, "fx/live")
    assert scaled(lib, prog) == pytest.approx(0.25)
    return prog, main, value


def scaled(lib, prog) -> float:
    """The rendered value with uScale = 1 (a new program starts with zeros: effects set their
    uniforms every frame)."""
    prog.set("uScale", 1.0)
    return float(render_pixel(lib.ctx, prog)[0])


def poll_twice(lib):
    """Two window polls (0.5 s of a running window): a file missing at both is missing."""
    return lib.poll() + lib.poll()


def where(prog) -> set[tuple[str, int]]:
    return {(e.file, e.line) for e in prog.errors}


def restore(path: Path, text: str) -> None:
    if path.is_dir():
        path.rmdir()
    elif os.path.lexists(path):
        path.unlink()
    save_like_editor(path, text)


def assert_recovers(lib, prog, path: Path, text: str, value: float = 0.25) -> None:
    restore(path, text)
    assert prog in lib.poll()
    assert prog.errors == [] and lib.errors() == []
    assert scaled(lib, prog) == pytest.approx(value)


@pytest.mark.parametrize("which", ["stage", "include"])
def test_a_file_replaced_by_a_folder_is_an_error_not_an_exception(lib, live, which):
    prog, main, value = live
    path = main if which == "stage" else value
    text = path.read_text()
    good = prog.program
    path.unlink()
    path.mkdir()
    assert poll_twice(lib) == [prog]  # IsADirectoryError escaped poll() before
    if which == "stage":
        assert where(prog) == {(lib.display(path), 1)}
    else:  # blamed on the #include line, naming the folder
        assert where(prog) == {(lib.display(main), 2)}
    assert "folder" in prog.errors[0].message
    assert prog.program is good and scaled(lib, prog) == pytest.approx(0.25)
    assert_recovers(lib, prog, path, text)


def test_a_named_pipe_never_blocks_a_poll(lib, live):
    prog, main, value = live
    text = value.read_text()
    value.unlink()
    os.mkfifo(value)
    finishes(lambda: poll_twice(lib))  # opening the pipe for reading would block forever
    assert where(prog) == {(lib.display(main), 2)}
    assert "named pipe" in prog.errors[0].message and prog.failed
    os.unlink(value)
    os.mkfifo(main.with_name("pipe.frag"))
    assert_recovers(lib, prog, value, text)


def test_a_device_as_an_include_is_an_error(lib, live, root):
    prog, main, value = live
    (root / "fx/device.glsl").symlink_to("/dev/zero")  # reading it would never end
    text = main.read_text()
    save_like_editor(main, text.replace('#include "live_value.glsl"',
                                        '#include "live_value.glsl"\n#include "device.glsl"'))
    assert lib.poll() == [prog]
    assert where(prog) == {(lib.display(main), 3)}
    # refused as a link out of the shader folder before anything asks what it is (issue 36)
    assert "a link out of the shader folder" in prog.errors[0].message
    assert_recovers(lib, prog, main, text)


def test_latin1_bytes_report_the_line_of_the_first_bad_byte(lib, live):
    prog, main, value = live
    text = value.read_text()
    value.write_bytes(b"// line 1\n// line 2\n// caf\xe9 on line 3\n" + text.encode())
    assert lib.poll() == [prog]
    [err] = prog.errors
    assert (err.file, err.line) == (lib.display(value), 3)  # line 0 before
    assert "not UTF-8" in err.message and "0xe9" in err.message and "column 7" in err.message
    assert str(err).startswith(f"{lib.display(value)}:3: ")
    assert_recovers(lib, prog, value, text)


def test_a_nul_byte_is_an_error_at_its_line(lib, live):
    prog, main, value = live
    text = value.read_text()
    save_like_editor(value, "// one\nfloat liveValue() { return 0.25; }\0\n")
    assert lib.poll() == [prog]
    assert where(prog) == {(lib.display(value), 2)} and "NUL" in prog.errors[0].message
    assert_recovers(lib, prog, value, text)


def test_a_huge_file_is_refused_quickly(lib, live):
    prog, main, value = live
    text = value.read_text()
    value.write_bytes(text.encode() + b"//" + b"x" * (MAX_SOURCE_BYTES + 10) + b"\n")
    assert lib.poll() == [prog]  # refused from its size, before its text is read
    assert where(prog) == {(lib.display(value), 1)} and "MiB" in prog.errors[0].message
    assert_recovers(lib, prog, value, text)


def test_an_unreadable_file_is_an_error(lib, live, monkeypatch):
    prog, main, value = live
    text = value.read_text()
    real_open = os.open

    def refuse(path, *args, **kw):  # the suite may run as root, which chmod cannot stop
        if Path(path) == value.resolve():
            raise PermissionError(13, "Permission denied", str(path))
        return real_open(path, *args, **kw)

    monkeypatch.setattr(os, "open", refuse)
    save_like_editor(value, "float liveValue() { return 0.5; }\n")
    assert lib.poll() == [prog]
    assert where(prog) == {(lib.display(value), 1)}
    assert "Permission denied" in prog.errors[0].message
    monkeypatch.undo()
    assert_recovers(lib, prog, value, text)


def test_an_edit_of_the_same_size_in_the_same_clock_tick_is_seen(lib, live):
    prog, main, value = live
    before = value.stat()
    with open(value, "w") as f:  # in place: same inode, same size
        f.write("float liveValue() { return 0.75; }\n")
    os.utime(value, ns=(before.st_atime_ns, before.st_mtime_ns))  # the same mtime tick
    assert value.stat().st_size == before.st_size and value.stat().st_ino == before.st_ino
    assert lib.poll() == [prog]  # (mtime, size, inode) alone cannot see it: the hash does
    assert scaled(lib, prog) == pytest.approx(0.75)


@pytest.mark.parametrize("which", ["stage", "include"])
def test_delete_then_recreate_reloads(lib, live, which):
    prog, main, value = live
    path = main if which == "stage" else value
    text = path.read_text()
    path.unlink()
    assert lib.poll() == []  # one poll's grace: a save may be in progress
    assert prog.errors == []
    assert lib.poll() == [prog]  # still missing: an error, the last good program renders
    if which == "stage":
        assert where(prog) == {(lib.display(path), 1)}
        assert "not found" in prog.errors[0].message
    else:
        assert where(prog) == {(lib.display(main), 2)}
        assert "cannot find include" in prog.errors[0].message
    assert lib.poll() == []  # the error is not recompiled on every poll
    assert scaled(lib, prog) == pytest.approx(0.25)
    assert_recovers(lib, prog, path, text.replace("0.25", "0.5") if which == "include" else text,
                    0.5 if which == "include" else 0.25)


def test_a_missing_include_is_still_watched_so_restoring_it_recompiles(lib, root):
    # live.frag → middle.glsl → leaf.glsl: a compile while middle.glsl is missing cannot see
    # leaf.glsl; restoring middle.glsl (or any of the old include set) must recompile
    main = write(root, "fx/chain.frag", '#version 330 core\n#include "middle.glsl"\n'
                                        "out vec4 c;\nvoid main() { c = vec4(middle()); }\n")
    middle = write(root, "fx/middle.glsl",
                   '#include "leaf.glsl"\nfloat middle() { return leaf(); }\n')
    leaf = write(root, "fx/leaf2.glsl", "float leaf() { return 0.25; }\n")
    save_like_editor(middle, '#include "leaf2.glsl"\nfloat middle() { return leaf(); }\n')
    prog = program(lib, "fx/chain")
    assert leaf.resolve() in prog.files
    text = middle.read_text()
    middle.unlink()
    poll_twice(lib)
    assert where(prog) == {(lib.display(main), 2)}
    # the previous include set stays watched while the compile fails
    assert middle.resolve() in prog.stamps and leaf.resolve() in prog.stamps
    save_like_editor(leaf, "float leaf() { return 0.5; }\n")
    assert lib.poll() == [prog] and prog.errors  # middle.glsl is still missing
    save_like_editor(middle, text)
    assert lib.poll() == [prog] and prog.errors == []
    assert scaled(lib, prog) == pytest.approx(0.5)
    assert leaf.resolve() in prog.files


def test_an_include_that_appears_where_it_was_missing_recompiles(lib, root):
    main = write(root, "fx/later.frag", '#version 330 core\n#include "later.glsl"\n'
                                        "out vec4 c;\nvoid main() { c = vec4(later()); }\n")
    write(root, "fx/later.glsl", "float later() { return 0.25; }\n")
    prog = program(lib, "fx/later")
    (root / "fx/later.glsl").unlink()
    poll_twice(lib)
    assert where(prog) == {(lib.display(main), 2)}
    write(root, "common/later.glsl", "float later() { return 0.125; }\n")  # found in common/
    assert lib.poll() == [prog] and prog.errors == []
    assert scaled(lib, prog) == pytest.approx(0.125)


@pytest.mark.parametrize("edit", ["itself", "cycle"])
def test_include_cycles_are_included_once(lib, live, root, edit):
    prog, main, value = live
    if edit == "itself":
        save_like_editor(main, VALUE_FRAG.replace("out vec4", '#include "live.frag"\nout vec4'))
    else:
        save_like_editor(value, '#include "live.frag"\nfloat liveValue() { return 0.5; }\n')
    assert lib.poll() == [prog]
    assert prog.errors == []
    assert scaled(lib, prog) == pytest.approx(0.5 if edit == "cycle" else 0.25)


def test_include_of_a_folder_is_an_error_at_the_include(lib, live, root):
    prog, main, value = live
    (root / "fx/folder.glsl").mkdir()
    save_like_editor(main, VALUE_FRAG.replace("uniform float", '#include "folder.glsl"\n'
                                                               "uniform float"))
    assert lib.poll() == [prog]
    assert where(prog) == {(lib.display(main), 3)} and "folder" in prog.errors[0].message


@pytest.mark.parametrize("text, line", [
    ("", 1),  # emptied
    ("// comment only\nout vec4 fragColor;\nvoid main() { fragColor = vec4(1.0); }\n", 2),
])
def test_an_emptied_file_or_a_removed_version(lib, live, text, line):
    prog, main, value = live
    save_like_editor(main, text)
    assert lib.poll() == [prog]
    assert where(prog) == {(lib.display(main), line)} and "#version" in prog.errors[0].message


def test_a_one_megabyte_line_is_reported_at_its_line(lib, live):
    prog, main, value = live
    save_like_editor(value, "float liveValue() { return 0.25; }\nfloat q = " + "x" * 1_000_000
                     + ";\n")
    assert lib.poll() == [prog]
    assert where(prog) == {(lib.display(value), 2)}
    assert all(len(e.message) <= 600 for e in prog.errors)  # no megabyte in the panel
    save_like_editor(value, "float liveValue() { return 0.25; }\n// " + "x" * 1_000_000 + "\n")
    assert lib.poll() == [prog] and prog.errors == []  # a long comment is fine


def test_user_line_directives_do_not_break_the_mapping(lib, live):
    prog, main, value = live
    save_like_editor(value, "#line 500 7\nfloat liveValue() {\n    return nope;\n}\n")
    assert lib.poll() == [prog]
    assert where(prog) == {(lib.display(value), 3)}


# ---- link errors: blamed on a declaration, never on the first stage file -----------------------

def test_a_varying_qualifier_mismatch_is_blamed_on_the_edited_declaration(lib, live):
    prog, main, value = live
    vert = Path(lib.root) / "common/fullscreen.vert"
    save_like_editor(main, VALUE_FRAG.replace("uniform float uScale;",
                                              "uniform float uScale;\nflat in vec2 vUV;"))
    assert lib.poll() == [prog]
    [err] = prog.errors
    assert (err.file, err.line) == (lib.display(main), line_of(main, "flat in vec2 vUV"))
    assert "vUV" in err.message and "link" in err.message
    assert f"{lib.display(vert)}:{line_of(vert, 'out vec2 vUV')}" in err.message  # also there
    # the same mismatch made in the vertex file (saved last) is blamed there
    vert_text = vert.read_text()
    save_like_editor(main, VALUE_FRAG.replace("uniform float uScale;",
                                              "uniform float uScale;\nin vec2 vUV;"))
    save_like_editor(vert, vert_text.replace("out vec2 vUV;", "noperspective out vec2 vUV;"))
    later = main.stat().st_mtime_ns + 1_000_000_000
    os.utime(vert, ns=(later, later))
    assert lib.poll() == [prog]
    assert where(prog) == {(lib.display(vert), line_of(vert, "noperspective out"))}
    save_like_editor(vert, vert_text)
    assert lib.poll() == [prog] and prog.errors == []


def test_a_uniform_declared_with_two_types_is_blamed_on_a_declaration(lib, root):
    vert = write(root, "fx/two.vert", FULLSCREEN_VERT.replace(
        "out vec2 vUV;", "out vec2 vUV;\nuniform float uShared;").replace(
        "vUV = p;", "vUV = p * uShared;"))
    frag = write(root, "fx/two.frag", "#version 330 core\nin vec2 vUV;\nuniform int uShared;\n"
                                      "out vec4 c;\nvoid main() { c = vec4(vUV, uShared, 1); }\n")
    with pytest.raises(ShaderCompileError) as info:
        lib.program("fx/two")
    [err] = info.value.errors
    assert "uShared" in err.message
    assert (err.file, err.line) in {(lib.display(vert), line_of(vert, "uniform float uShared")),
                                    (lib.display(frag), 3)}


def test_a_link_error_naming_nothing_points_at_the_fragment_stage(lib, live):
    prog, main, value = live
    save_like_editor(main, VALUE_FRAG.replace("void main()", "void notMain()"))
    assert lib.poll() == [prog]
    [err] = prog.errors
    assert (err.file, err.line) == (lib.display(main), 1)
    assert "main" in err.message and "fragment stage" in err.message


# ---- uniforms whose type changed in the GLSL ---------------------------------------------------

def test_a_uniform_whose_type_changed_is_converted_or_skipped_never_raised(lib, live):
    prog, main, value = live
    save_like_editor(main, VALUE_FRAG.replace("uniform float uScale;", "uniform int uScale;"))
    assert lib.poll() == [prog] and prog.errors == []  # int converts to float in GLSL
    prog.set("uScale", 1.6)  # raised ValueError before: now rounded
    assert prog.program["uScale"].value == 2 and prog.errors == []
    assert render_pixel(lib.ctx, prog)[0] == pytest.approx(0.5)
    prog.set("uScale", True)
    assert prog.program["uScale"].value == 1
    prog.set("uScale", (1.0, 2.0, 3.0))  # three numbers on an int: skipped and listed
    [err] = prog.errors
    assert (err.file, err.line) == (lib.display(main), line_of(main, "uniform int uScale"))
    assert "uScale" in err.message and "int" in err.message and "skipped" in err.message
    assert lib.errors() == [err]
    prog.set("uScale", (1.0, 2.0, 3.0))  # listed once, not once a frame
    assert len(prog.errors) == 1
    assert render_pixel(lib.ctx, prog)[0] == pytest.approx(0.25)  # kept its last value

    save_like_editor(main, VALUE_FRAG.replace("uniform float uScale;", "uniform vec3 uScale3;")
                     .replace("* uScale", "* uScale3.y"))
    assert lib.poll() == [prog] and prog.errors == []
    prog.set("uScale3", 2.0)  # a scalar fills every component
    assert prog.program["uScale3"].value == pytest.approx((2.0, 2.0, 2.0))
    prog.set("uScale3", np.eye(4))  # a matrix on a vector: skipped and listed
    assert where(prog) == {(lib.display(main), line_of(main, "uniform vec3 uScale3"))}
    assert render_pixel(lib.ctx, prog)[0] == pytest.approx(0.5)


def test_a_uniform_array_whose_type_changed_is_skipped_and_listed(lib, root):
    main = write(root, "fx/rows.frag", """\
        #version 330 core
        uniform vec4 uRows[2];
        out vec4 fragColor;
        void main() { fragColor = uRows[0] + uRows[1]; }
        """)
    prog = program(lib, "fx/rows")
    prog.set_array("uRows", [(0.25, 0.0, 0.0, 0.0), (0.25, 0.0, 0.0, 0.0)])
    assert render_pixel(lib.ctx, prog)[0] == pytest.approx(0.5)
    prog.set_array("uRows", [(1.0, 2.0, 3.0)])  # rows of three on vec4 rows: raised before
    assert where(prog) == {(lib.display(main), 2)} and "uRows" in prog.errors[0].message
    save_like_editor(main, main.read_text().replace("vec4 uRows[2]", "ivec4 uRows[2]")
                     .replace("= uRows[0] + uRows[1]", "= vec4(uRows[0] + uRows[1])"))
    assert lib.poll() == [prog] and prog.errors == []
    prog.set_array("uRows", [(0.25, 0.0, 0.0, 0.0)])  # float bytes in an int array: refused
    assert where(prog) == {(lib.display(main), 2)}
    assert "ivec4" in prog.errors[0].message


# ---- poll() never raises -----------------------------------------------------------------------

def test_poll_turns_unexpected_exceptions_into_listed_errors(lib, live, monkeypatch):
    prog, main, value = live
    calls = []

    def broken_callback(p):
        calls.append(p)
        raise RuntimeError("a reload callback's bug")

    prog.on_reload.append(broken_callback)
    save_like_editor(value, "float liveValue() { return 0.5; }\n")
    assert lib.poll() == [prog]
    assert calls == [prog] and prog.generation == 2  # the reload itself succeeded
    assert not prog.failed
    [err] = prog.errors
    assert err.message.startswith("internal: reload callback") and "a reload callback's bug" \
        in err.message and err.line == 1
    prog.on_reload.remove(broken_callback)

    def explode(*args, **kw):
        raise KeyError("driver exploded")

    monkeypatch.setattr(lib.ctx.__class__, "program", explode)
    save_like_editor(value, "float liveValue() { return 0.125; }\n")
    assert lib.poll() == [prog]
    assert [e.message for e in prog.errors] == ["internal: compile failed: KeyError: "
                                                "'driver exploded'"]
    assert scaled(lib, prog) == pytest.approx(0.5)
    assert lib.poll() == []  # not retried on every poll
    monkeypatch.undo()
    assert_recovers(lib, prog, value, "float liveValue() { return 0.125; }\n", 0.125)


# ---- @param annotations broken by a live edit --------------------------------------------------

ANNOTATED_FRAG = """\
    #version 330 core
    uniform float uGain; // @param 0.5 [0, 1] step=0.01 how bright
    out vec4 fragColor;
    void main() { fragColor = vec4(uGain, 0.0, 0.0, 1.0); }
    """


@contextmanager
def annotated_effect(gl, root):
    """An effect ``fx`` drawing fx/annotated.frag (ANNOTATED_FRAG), fx.gain set to 0.75:
    (gpu, params, fx, prog, frag, the shader's text); the Gpu is released after."""
    from app.effects.base import Effect
    from app.gpu.device import Gpu
    from app.gpu.programs import fullscreen
    from app.params import ParamSet

    class Annotated(Effect):
        name = "fx"
        programs = (fullscreen("fx/annotated"),)

    frag = write(root, "fx/annotated.frag", ANNOTATED_FRAG)
    text = frag.read_text()
    gpu = Gpu(gl, root)
    try:
        params = ParamSet(Annotated.declare(gpu.shaders))
        fx = Annotated(gpu, params)
        prog = fx.program(Annotated.programs[0])
        params.set("fx.gain", 0.75)
        yield gpu, params, fx, prog, frag, text
    finally:
        gpu.release()


@pytest.mark.parametrize("broken, why", [
    ("// @param 0.5 [0, 1", "range"),
    ("// @param 0.5 [0, 1] step=abc", "step=abc"),  # a ValueError escaped before
    ("// @param 5 [0, 1]", "out of range"),
    ("// @param", "default"),
    ("// @param true [0, 1]", "true"),
])
def test_a_broken_param_after_a_reload_is_listed_and_keeps_the_last_declaration(gl, root, broken,
                                                                                 why):
    with annotated_effect(gl, root) as (gpu, params, fx, prog, frag, text):
        save_like_editor(frag, text.replace("// @param 0.5 [0, 1] step=0.01 how bright", broken))
        assert gpu.shaders.poll() == [prog]  # raised ParamError (or ValueError) before
        [err] = prog.errors
        assert (err.file, err.line) == (gpu.shaders.display(frag), 2)
        assert err.message.startswith("@param") and why in err.message, err.message
        assert not prog.failed  # it reloaded; the panel lists the annotation's error
        spec = params.spec("fx.gain")
        assert (spec.lo, spec.hi, spec.step) == (0.0, 1.0, 0.01)  # the last good declaration
        assert params["fx.gain"] == 0.75
        fx.apply_params(prog)
        assert render_pixel(gl, prog)[0] == pytest.approx(0.75)

        save_like_editor(frag, text.replace("[0, 1]", "[0, 2]"))
        assert gpu.shaders.poll() == [prog] and prog.errors == []
        assert params.spec("fx.gain").hi == 2.0 and params["fx.gain"] == 0.75


def test_a_uniform_type_change_through_apply_params_never_raises(gl, root):
    """A float parameter whose uniform became an int (its annotation now unfit) or a vec3."""
    with annotated_effect(gl, root) as (gpu, params, fx, prog, frag, text):
        save_like_editor(frag, text.replace("uniform float uGain", "uniform int uGain")
                         .replace("vec4(uGain,", "vec4(float(uGain),"))
        assert gpu.shaders.poll() == [prog]
        # 0.5 is no int default: listed at its line, the float declaration kept
        assert [(e.line, "integer" in e.message) for e in prog.errors] == [(2, True)]
        fx.apply_params(prog)  # raised ValueError before: 0.75 rounds to 1
        assert prog.program["uGain"].value == 1
        assert render_pixel(gl, prog)[0] == pytest.approx(1.0)

        save_like_editor(frag, text.replace("uniform float uGain; // @param 0.5 [0, 1] step=0.01 "
                                            "how bright", "uniform vec2 uGain;")
                         .replace("vec4(uGain, 0.0,", "vec4(uGain,"))
        assert gpu.shaders.poll() == [prog] and prog.errors == []
        fx.apply_params(prog)  # the scalar fills both components
        assert prog.program["uGain"].value == pytest.approx((0.75, 0.75))


def test_a_vertex_array_is_never_reused_for_a_new_buffer(gl, root):
    """The cache of vertex arrays is keyed by the buffers' ids: a buffer dropped by its owner
    must not let a new buffer take its id and draw through the old array."""
    from app.gpu.device import Gpu

    write(root, "fx/flat.vert", "#version 330 core\nin vec2 aPos;\n"
          "void main() { gl_Position = vec4(aPos, 0.0, 1.0); }\n")
    write(root, "fx/flat.frag", "#version 330 core\nout vec4 c;\nvoid main() { c = vec4(1); }\n")
    gpu = Gpu(gl, root)
    try:
        prog = gpu.shaders.program("fx/flat")
        for _ in range(50):
            buf = gl.buffer(b"\0" * 24)
            vao = prog.vao([(buf, "2f", "aPos")])
            assert vao.extra[0][0] is buf  # the array keeps its own buffer alive
            del buf  # without the array's reference the next buffer could take its id
        assert len(prog._vaos) == 50  # each buffer got its own array, none a stale one
    finally:
        gpu.release()
