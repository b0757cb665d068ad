"""The shader library (DESIGN.md "Shader library"; issue 2 item 3) without a context: where
the shaders come from (--shaders, $NATURA_SHADERS, the project's glsl/); reading GLSL files
(folders, named pipes, devices, unreadable, non-UTF-8, NUL and huge files are errors with a line,
never a hang); includes, the stamps live reload compares, error lines and link-error blame;
converting a value to a uniform whose GLSL type changed.
"""

from __future__ import annotations

import os

import pytest

from app import DEFAULT_SHADER_ROOT
from app.errors import UsageError
from app.gpu.shaders import (
    MAX_SOURCE_BYTES,
    SHADER_ENV,
    PreprocessError,
    Program,
    ShaderLibrary,
    SourceError,
    _convert,
    _stamp,
    read_source,
    resolve_shader_root,
    source_lines,
)
from app.params import parse_glsl_annotations
from tests.helpers.hang import finishes

# ---- where the shaders come from ---------------------------------------------------------------

def test_resolve_shader_root(tmp_path, monkeypatch):
    arg_dir, env_dir = tmp_path / "from_arg", tmp_path / "from_env"
    (arg_dir / "common").mkdir(parents=True)  # laid out like glsl/
    (env_dir / "common").mkdir(parents=True)
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
    assert "--shaders" in str(info.value) and a_file.name in str(info.value)
    assert "is not a directory" in str(info.value) and info.value.exit_code == 2
    (tmp_path / "bare").mkdir()  # a folder, but not laid out like glsl/
    with pytest.raises(UsageError, match="has no common/ folder"):
        resolve_shader_root(str(tmp_path / "bare"))
    monkeypatch.setenv(SHADER_ENV, str(tmp_path / "missing"))
    with pytest.raises(UsageError) as info:
        resolve_shader_root(None)
    assert SHADER_ENV in str(info.value) and "missing" in str(info.value)


# ---- reading GLSL files: never blocks, never raises anything but SourceError -------------------

def test_read_source_refuses_what_is_not_a_text_file(tmp_path):
    folder = tmp_path / "folder.glsl"
    folder.mkdir()
    pipe = tmp_path / "pipe.glsl"
    os.mkfifo(pipe)
    device = tmp_path / "device.glsl"
    device.symlink_to("/dev/zero")
    cases = {folder: "a folder", pipe: "a named pipe", device: "a device",
             tmp_path / "missing.glsl": "not found"}
    for path, why in cases.items():
        with pytest.raises(SourceError) as info:
            finishes(lambda: read_source(path))  # a pipe opened for reading blocks forever
        assert info.value.line == 1 and why in info.value.reason, (path, info.value.reason)


def test_read_source_reports_the_line_of_bad_bytes(tmp_path):
    latin1 = tmp_path / "latin1.glsl"
    latin1.write_bytes("// one\n// two\n// caf\u00e9\n".encode("latin-1"))
    with pytest.raises(SourceError) as info:
        read_source(latin1)
    assert info.value.line == 3 and "0xe9" in info.value.reason and "column 7" in info.value.reason
    nul = tmp_path / "nul.glsl"
    nul.write_bytes(b"// one\nfloat\0 x;\n")
    with pytest.raises(SourceError) as info:
        read_source(nul)
    assert info.value.line == 2 and "NUL" in info.value.reason and "column 6" in info.value.reason
    bom = tmp_path / "bom.glsl"
    bom.write_bytes(b"\xef\xbb\xbf#version 330 core\n")
    assert read_source(bom) == "#version 330 core\n"  # a BOM would hide #version


def test_read_source_bounds_the_read(tmp_path):
    huge = tmp_path / "huge.glsl"
    huge.write_bytes(b"/" * (MAX_SOURCE_BYTES + 1))
    with pytest.raises(SourceError) as info:
        read_source(huge)
    assert info.value.line == 1 and "MiB" in info.value.reason
    fits = tmp_path / "fits.glsl"
    fits.write_bytes(b"// " + b"x" * 1_000_000 + b"\n")  # a 1 MB line is fine
    assert len(read_source(fits)) == 1_000_004


def test_read_source_reports_an_unreadable_file(tmp_path, monkeypatch):
    path = tmp_path / "secret.glsl"
    path.write_text("float x;\n")
    real_open = os.open

    def refuse(p, *args, **kw):  # root reads a chmod 000 file, so the refusal is simulated
        if str(p) == str(path):
            raise PermissionError(13, "Permission denied", str(p))
        return real_open(p, *args, **kw)

    monkeypatch.setattr(os, "open", refuse)
    with pytest.raises(SourceError) as info:
        read_source(path)
    assert info.value.line == 1 and "Permission denied" in info.value.reason


def test_lines_are_counted_as_the_compiler_counts_them():
    text = ("// a \u2028 line separator and a \x0c form feed\r\n"
            "uniform float uX; // @param 2 [0, 1]\n")
    assert len(text.splitlines()) == 4 and len(source_lines(text)) == 2
    problems: list = []
    assert parse_glsl_annotations(text, "fx", "f.glsl", problems=problems) == []
    assert problems == [(2, "default fx.x=2.0 is out of range: allowed a number in [0, 1]")]


# ---- preprocessing and stamps (no context) ------------------------------------------------------

@pytest.fixture
def lib(tmp_path):
    root = tmp_path / "glsl"
    (root / "common").mkdir(parents=True)
    (root / "fx").mkdir()
    return ShaderLibrary(None, root)


def write(path, text):
    path.write_text(text)
    return path


def test_include_of_a_folder_is_an_error_at_the_include_line(lib):
    (lib.root / "fx/dir.glsl").mkdir()
    main = write(lib.root / "fx/a.frag", '#version 330 core\n// two\n#include "dir.glsl"\n')
    with pytest.raises(PreprocessError) as info:
        lib.preprocess(main)
    assert (info.value.error.file, info.value.error.line) == (lib.display(main), 3)
    assert "folder" in info.value.error.message


def test_include_cycles_and_self_includes_expand_once(lib):
    main = write(lib.root / "fx/a.frag", '#version 330 core\n#include "a.frag"\n'
                                         '#include "b.glsl"\nvoid main() {}\n')
    write(lib.root / "fx/b.glsl", '#include "a.frag"\n#include "b.glsl"\nfloat b;\n')
    src = lib.preprocess(main)
    assert src.text.count("float b;") == 1 and src.text.count("void main") == 1
    assert [p.name for p in src.files] == ["a.frag", "b.glsl"]


def test_a_missing_include_is_watched_wherever_it_may_appear(lib):
    main = write(lib.root / "fx/a.frag", '#version 330 core\n#include "later.glsl"\n')
    with pytest.raises(PreprocessError) as info:
        lib.preprocess(main)
    watched = {p for p, stamp in info.value.stamps.items() if stamp is None}
    assert watched == {(lib.root / "fx/later.glsl").resolve(),
                       (lib.root / "common/later.glsl").resolve(),
                       (lib.root / "later.glsl").resolve()}


def test_a_vanished_file_is_given_one_poll_then_counts(lib):
    main = write(lib.root / "fx/a.frag", "#version 330 core\n")
    prog = Program(lib, "fx/a", {}, {"frag": main})
    prog.stamps = {main: _stamp(main)}
    assert not prog.changed_on_disk()
    main.unlink()
    assert not prog.changed_on_disk()  # mid-save: an editor moved the original away
    assert prog.changed_on_disk()  # still missing at the next poll: recompile, list the error
    write(main, "#version 330 core\n")
    prog.stamps = {main: None}  # what the failed compile recorded
    assert prog.changed_on_disk()  # its reappearance recompiles


def test_the_stamp_sees_a_same_size_edit_in_the_same_tick(lib):
    path = write(lib.root / "fx/a.glsl", "float a = 1.0;\n")
    before = path.stat()
    old = _stamp(path)
    with open(path, "w") as f:
        f.write("float a = 2.0;\n")
    os.utime(path, ns=(before.st_atime_ns, before.st_mtime_ns))
    assert path.stat().st_ino == before.st_ino and path.stat().st_size == before.st_size
    assert _stamp(path) != old


# ---- the remembered expansions (ShaderLibrary.preprocess) ------------------------------------

def _no_expansion(lib, monkeypatch):
    """Make a fresh expansion fail loudly: what follows must come from the memo."""
    def refuse(*args, **kw):
        raise AssertionError("expanded again")
    monkeypatch.setattr(lib, "_expand", refuse)


def test_an_unchanged_expansion_is_given_again_without_expanding(lib, monkeypatch):
    main = write(lib.root / "fx/a.frag", '#version 330 core\n#include "b.glsl"\nvoid main() {}\n')
    write(lib.root / "common/b.glsl", "float b;\n")
    first = lib.preprocess(main, {"FLAG": True})
    first.files.append(main)  # a caller's change to its copy reaches no other caller
    _no_expansion(lib, monkeypatch)
    again = ShaderLibrary(None, lib.root).preprocess(main, {"FLAG": True})  # another session
    assert again.text == first.text and "#define FLAG 1" in again.text
    assert again.files == first.files[:-1] and again.stamps == first.stamps
    monkeypatch.undo()
    # defines are told apart by their GLSL text: True, 1 and 1.0 are not one key
    assert "#define FLAG 1.0" in lib.preprocess(main, {"FLAG": 1.0}).text


def test_every_change_an_expansion_depended_on_expands_again(lib):
    main = write(lib.root / "fx/a.frag", '#version 330 core\n#include "b.glsl"\n')
    inc = write(lib.root / "common/b.glsl", "float b = 1.0;\n")
    assert "float b = 1.0;" in lib.preprocess(main).text
    # an edit of the same size in the same tick of the clock (the content hash sees it)
    before = inc.stat()
    with open(inc, "w") as f:
        f.write("float b = 2.0;\n")
    os.utime(inc, ns=(before.st_atime_ns, before.st_mtime_ns))
    assert "float b = 2.0;" in lib.preprocess(main).text
    # a file of that name appearing where the include is looked for first
    near = write(lib.root / "fx/b.glsl", "float near;\n")
    src = lib.preprocess(main)
    assert "float near;" in src.text and near.resolve() in src.files
    near.unlink()
    assert "float b = 2.0;" in lib.preprocess(main).text
    # a link retargeted: the same place now names another file
    write(lib.root / "common/c1.glsl", "float c1;\n")
    write(lib.root / "common/c2.glsl", "float c2;\n")
    link = lib.root / "common/c.glsl"
    link.symlink_to("c1.glsl")
    write(main, '#version 330 core\n#include "c.glsl"\n')
    assert "float c1;" in lib.preprocess(main).text
    link.unlink()
    link.symlink_to("c2.glsl")
    assert "float c2;" in lib.preprocess(main).text


def test_a_failed_expansion_is_never_remembered(lib):
    main = write(lib.root / "fx/a.frag", '#version 330 core\n#include "later.glsl"\n')
    for _ in range(2):  # the same error, from the full path, each time
        with pytest.raises(PreprocessError) as info:
            lib.preprocess(main)
        assert (info.value.error.line, "cannot find include") == (
            2, info.value.error.message[:len("cannot find include")])
    write(lib.root / "common/later.glsl", "float later;\n")
    assert "float later;" in lib.preprocess(main).text
    (lib.root / "common/later.glsl").write_bytes(b"float \xff;\n")
    with pytest.raises(PreprocessError) as info:
        lib.preprocess(main)
    assert "not UTF-8" in info.value.error.message and info.value.error.line == 1


def test_unlocated_messages_get_a_real_line(lib):
    main = write(lib.root / "fx/a.frag", "#version 330 core\nout vec4 c;\n\nvoid main() {}\n")
    errors = lib.map_errors("error: something without a place\n0:0(1): error: line zero",
                            [main], main)
    assert [(e.line, e.message) for e in errors] == [(4, "error: something without a place"),
                                                    (1, "error: line zero")]


def test_link_errors_blame_the_newest_declaration(lib):
    vert = write(lib.root / "fx/a.vert", "#version 330 core\nout vec2 vUV;\nvoid main() {}\n")
    frag = write(lib.root / "fx/a.frag", "#version 330 core\n\nflat in vec2 vUV;\n"
                                         "void main() {}\n")
    os.utime(vert, ns=(10**18, 10**18))
    os.utime(frag, ns=(2 * 10**18, 2 * 10**18))
    tables = {"vertex_shader": [vert], "fragment_shader": [frag]}
    message = ("error: vertex shader output `vUV' specifies no interpolation qualifier, but "
               "fragment shader input specifies flat interpolation qualifier")
    err = lib.blame_link(message, tables, frag)
    assert (err.file, err.line) == (lib.display(frag), 3)
    assert f"{lib.display(vert)}:2" in err.message
    os.utime(vert, ns=(3 * 10**18, 3 * 10**18))
    assert lib.blame_link(message, tables, frag).line == 2
    fallback = lib.blame_link("error: fragment shader lacks `main'", tables, frag)
    assert (fallback.file, fallback.line) == (lib.display(frag), 4)
    assert "void main line of the fragment stage" in fallback.message


class FakeUniform:
    def __init__(self, gl_type, dimension, array_length=1):
        self.gl_type, self.dimension, self.array_length = gl_type, dimension, array_length


@pytest.mark.parametrize("gl_type, dim, value, expected", [
    (0x1404, 1, 1.6, 2),  # float → int rounds
    (0x1404, 1, True, 1),  # bool → int
    (0x1406, 1, False, 0.0),  # bool → float
    (0x8B56, 1, 0.2, 1),  # a non-zero number is true
    (0x8B51, 3, 2.0, (2.0, 2.0, 2.0)),  # a scalar fills a vector
    (0x8B54, 3, (0.4, 1.6, -2.5), (0, 2, -2)),  # ivec3 from floats
    (0x1405, 1, -3.0, 0),  # uint clamps at 0
    (0x1406, 1, (1.0, 2.0), None),  # a vector on a scalar: refused
    (0x8B52, 4, (1.0, 2.0, 3.0), None),  # vec3 on a vec4: refused
    (0x1404, 1, float("nan"), None),
    (0x8B5E, 1, 0.0, None),  # samplers are bound by bind_textures only
    (0x1406, 1, "abc", None),
    (0x8B52, 4, 1.0, (1.0, 1.0, 1.0, 1.0)),
])
def test_uniform_values_are_converted_to_the_glsl_type(gl_type, dim, value, expected):
    assert _convert(FakeUniform(gl_type, dim), value) == expected
    assert _convert(FakeUniform(gl_type, dim, array_length=4), value) is None


def test_a_line_past_the_end_of_a_file_is_brought_back_into_it(lib):
    comment = write(lib.root / "fx/c.glsl", "float a;\n/* opened\nfloat b;\n")
    other = write(lib.root / "fx/d.glsl", "float a;\nfloat b;\n")
    log = ("0:212(1): preprocessor error: Unterminated comment\n"
           "1:99(1): error: something at the end")
    first, second = lib.map_errors(log, [comment, other], comment)
    assert (first.file, first.line) == (lib.display(comment), 2)  # where the /* is
    assert (second.file, second.line) == (lib.display(other), 2)
    assert "past the end" in second.message


# ---- what a shared folder may hold (issue 36) ----------------------------------------------------

def _opened(monkeypatch) -> list[str]:
    """Every path the library opens from now on."""
    opened: list[str] = []
    real_open = os.open

    def spy(path, *args, **kw):
        opened.append(os.path.abspath(path))
        return real_open(path, *args, **kw)

    monkeypatch.setattr(os, "open", spy)
    return opened


@pytest.mark.parametrize("include, why", [
    ("/etc/hostname", "is an absolute path"),
    ("../../../../../../../../etc/hostname", "leads out of the shader folder"),
    ("../../outside.glsl", "leads out of the shader folder"),
    ("link.glsl", "is a link out of the shader folder (LIB/fx/link.glsl)"),
    ("away/inside.glsl", "is a link out of the shader folder (LIB/fx/away/inside.glsl)"),
], ids=["absolute", "dot-dot-etc", "dot-dot", "link-out", "folder-link-out"])
def test_an_include_never_leaves_the_shader_folder(lib, monkeypatch, include, why):
    """Refused at the #include line, naming it, and never opened: an absolute path, a ``..``
    out of the root, a link (of the file, or of a folder on its way) that points out."""
    outside = lib.root.parent / "outside"
    outside.mkdir()
    write(outside / "inside.glsl", "float secret;\n")
    write(lib.root.parent / "outside.glsl", "float secret;\n")
    (lib.root / "fx/link.glsl").symlink_to(outside / "inside.glsl")
    (lib.root / "fx/away").symlink_to(outside)
    main = write(lib.root / "fx/a.frag", f'#version 330 core\n// two\n#include "{include}"\n')
    opened = _opened(monkeypatch)
    with pytest.raises(PreprocessError) as info:
        lib.preprocess(main)
    error = info.value.error
    assert (error.file, error.line) == (lib.display(main), 3)
    said = why.replace("LIB", lib.display(lib.root))
    assert error.message.startswith(f'include "{include}" {said}'), error.message
    assert "allowed a" in error.message and f"inside {lib.display(lib.root)}/" in error.message
    assert len(str(error)) < 400
    root = str(lib.root)
    assert all(p.startswith(root + os.sep) for p in opened), opened  # nothing outside read
    assert not any(p.startswith(str(outside)) or p.startswith("/etc") for p in opened)
    assert lib.include_children(main) == []  # the editor's include tree does not follow it


def test_a_link_that_stays_inside_is_followed(lib):
    """Inside the root, or into Natura's own glsl/ (a folder mounted by a link), a link is a
    file like any other."""
    write(lib.root / "common/real.glsl", "float real_one;\n")
    (lib.root / "fx/alias.glsl").symlink_to(lib.root / "common/real.glsl")
    (lib.root / "shipped").symlink_to(DEFAULT_SHADER_ROOT / "common")
    main = write(lib.root / "fx/a.frag", '#version 330 core\n#include "alias.glsl"\n'
                                         '#include "../shipped/math.glsl"\n')
    src = lib.preprocess(main)
    assert "float real_one;" in src.text
    assert (DEFAULT_SHADER_ROOT / "common/math.glsl").resolve() in src.files


def test_a_symlink_loop_is_an_error_at_its_line(lib):
    """A stage file that is a link to itself: its line 1, not an internal error blamed on
    another stage; an include that is one: at the #include line, naming it."""
    stage = lib.root / "fx/loop.frag"
    stage.symlink_to("loop.frag")
    with pytest.raises(PreprocessError) as info:
        lib.preprocess(stage)
    assert (info.value.error.file, info.value.error.line) == (lib.display(stage), 1)
    assert info.value.error.file.endswith("fx/loop.frag")
    assert info.value.error.message.startswith("is a symlink loop")
    (lib.root / "fx/round.glsl").symlink_to("round.glsl")
    main = write(lib.root / "fx/a.frag", '#version 330 core\n#include "round.glsl"\n')
    with pytest.raises(PreprocessError) as info:
        lib.preprocess(main)
    assert (info.value.error.file, info.value.error.line) == (lib.display(main), 2)
    assert info.value.error.message.startswith(
        f'include "round.glsl" is a symlink loop ({lib.display(lib.root)}/fx/round.glsl)')
    # fixing the link (a file in its place) is seen: the failure is never remembered
    (lib.root / "fx/round.glsl").unlink()
    write(lib.root / "fx/round.glsl", "float round_one;\n")
    assert "float round_one;" in lib.preprocess(main).text


@pytest.mark.parametrize("content", ["", "\n\n  \t\n"])
def test_an_empty_include_is_an_error_at_its_include(lib, content):
    """The code a file was included for is gone: named at the #include, with the file (a
    comment alone is not empty: the compile names what is missing)."""
    inc = write(lib.root / "fx/gone.glsl", content)
    main = write(lib.root / "fx/a.frag", '#version 330 core\n\n#include "gone.glsl"\n')
    with pytest.raises(PreprocessError) as info:
        lib.preprocess(main)
    error = info.value.error
    assert (error.file, error.line) == (lib.display(main), 3)
    assert error.message == (f'include "gone.glsl" ({lib.display(inc)}) is empty: allowed a '
                             "GLSL file holding the code included from it (restore it)")
    assert inc.resolve() in info.value.stamps  # watched: filling it recompiles
    write(inc, "// only a comment\n")
    assert "only a comment" in lib.preprocess(main).text


def test_a_missing_include_names_every_place_it_was_looked_for(lib):
    main = write(lib.root / "fx/a.frag", '#version 330 core\n#include "later.glsl"\n')
    with pytest.raises(PreprocessError) as info:
        lib.preprocess(main)
    r = lib.display(lib.root)
    assert info.value.error.message == (
        f'cannot find include "later.glsl" (no {r}/fx/later.glsl, {r}/common/later.glsl, '
        f"{r}/later.glsl): allowed a GLSL file at one of them")


def test_declaring_parameters_names_an_include_that_cannot_be_read(tmp_path):
    """The parameters of a file that is not there are unknown: declaring them says which
    include is missing (before: a later --set named an unknown parameter)."""
    import shutil

    from app.effects.sky.effect import Sky

    copy = tmp_path / "d"
    shutil.copytree(DEFAULT_SHADER_ROOT, copy)
    library = ShaderLibrary(None, copy)
    assert any(p.name == "sky.sun_color" for p in Sky.glsl_params(library))
    (copy / "sky/sky_radiance.glsl").unlink()
    with pytest.raises(UsageError) as info:
        Sky.glsl_params(library)
    message = str(info.value)
    assert message.startswith(f"{library.display(copy / 'sky/sky.frag')}:4: cannot find include "
                              '"sky_radiance.glsl"'), message
    assert info.value.exit_code == 2
    problems: list = []  # the window's reload path lists, never raises
    Sky.glsl_params(library, problems)


def test_every_shipped_stage_preprocesses():
    """Natura's own includes (``../common/x.glsl``, ``ocean/waves.glsl``…) all stay inside."""
    from app.cli import program_specs

    library = ShaderLibrary(None)
    count = 0
    for spec in program_specs():
        for path in library.stage_files(spec.name, **spec.stages()).values():
            library.preprocess(path, dict(spec.defines))
            count += 1
    assert count > 200
