"""What the window's shader editor does, without ImGui: the running scene's programs and the
include tree of each, the compiler's ``file:line`` errors as markers of one file, saving a file
atomically (its permissions kept, a change made on disk meanwhile never lost), and the first
save of Natura's own shaders going into a copy (``natura shaders copy``) instead.

The window (app/ui/editor.py) draws it; the shader library recompiles a saved file on its next
poll, as it does for any editor's save.
"""

from __future__ import annotations

import contextlib
import hashlib
import os
import shutil
from dataclasses import dataclass, field
from pathlib import Path

from .. import DEFAULT_SHADER_ROOT
from ..errors import UsageError, quote
from ..gpu.shaders import ShaderError, ShaderLibrary, read_source, resolve_shader_root
from ..imageio import (
    _LIVE,
    _remove,
    check_new_folder,
    expand,
    file_mode,
    temp_name_in,
    write_text_atomic,
)

#: the folder the first save offers when the shaders are Natura's own
DEFAULT_COPY = "my-glsl"


@dataclass
class Node:
    """A file of a program's include tree."""

    path: Path
    label: str                      # as messages name it (glsl/sky/sky.frag)
    children: list["Node"] = field(default_factory=list)


@dataclass
class ProgramTree:
    name: str
    stages: list[Node]              # one tree per stage file
    errors: list[ShaderError]


def include_tree(library: ShaderLibrary, path: Path, seen: set[Path] | None = None) -> Node:
    """``path`` and what it includes, recursively; a file already shown higher up in the same
    tree is listed once more without its children (the preprocessor includes it once)."""
    seen = set() if seen is None else seen
    path = Path(path).resolve()
    node = Node(path, library.display(path))
    if path in seen:
        return node
    seen.add(path)
    for child in library.include_children(path):
        node.children.append(include_tree(library, child, seen))
    return node


def program_trees(library: ShaderLibrary) -> list[ProgramTree]:
    """The running scene's programs (those its session compiled), by name, each with the
    include tree of its stage files and its current errors."""
    out = []
    for prog in sorted(library.programs(), key=lambda p: p.name):
        stages = [include_tree(library, p) for p in prog.stage_paths.values()]
        out.append(ProgramTree(prog.name, stages, list(prog.errors)))
    return out


def markers(errors, library: ShaderLibrary, path: Path) -> dict[int, str]:
    """The errors that blame ``path``, as {zero-based line: the whole messages of that line}
    (an error without a line goes on the first)."""
    label = library.display(Path(path))
    out: dict[int, list[str]] = {}
    for e in errors:
        if e.file == label:
            out.setdefault(max(e.line, 1) - 1, []).append(str(e))
    return {line: "\n".join(dict.fromkeys(msgs)) for line, msgs in out.items()}


def is_natura_own(root: Path) -> bool:
    """Whether ``root`` is the shader folder that ships with Natura (never written to)."""
    try:
        return Path(root).resolve() == DEFAULT_SHADER_ROOT.resolve()
    except OSError:
        return False


def digest(text: str) -> str:
    return hashlib.sha256(text.encode("utf-8")).hexdigest()


@dataclass
class OpenFile:
    """A file open in the editor: what it held on disk when opened or last saved."""

    path: Path
    disk_digest: str
    text: str

    @classmethod
    def open(cls, path: Path) -> "OpenFile":
        text = read_source(Path(path))
        return cls(Path(path), digest(text), text)

    def changed_on_disk(self) -> bool:
        try:
            return digest(read_source(self.path)) != self.disk_digest
        except Exception:  # noqa: BLE001 - gone or unreadable counts as changed
            return True


def save(open_file: OpenFile, text: str, overwrite_disk_change: bool = False) -> Path:
    """Write ``text`` over the open file atomically (a temporary file beside it renamed over
    it), keeping the file's permissions. A file changed on disk since it was opened is not
    overwritten unless ``overwrite_disk_change`` (one line says so); inside Natura's own
    shaders nothing is written."""
    path = open_file.path
    if path.resolve().is_relative_to(DEFAULT_SHADER_ROOT.resolve()):
        raise UsageError(f"{quote(str(path))} is one of Natura's own shaders: allowed a save "
                         "into a copy (natura shaders copy DIR)")
    if not overwrite_disk_change and open_file.changed_on_disk():
        raise UsageError(f"{quote(str(path))} changed on disk since it was opened: allowed "
                         "Reload (take the disk's version) or Overwrite")
    try:
        mode = path.stat().st_mode & 0o7777
    except OSError:
        mode = file_mode()
    write_text_atomic(path, text, force=True)
    with contextlib.suppress(OSError):
        os.chmod(path, mode)
    open_file.text = text
    open_file.disk_digest = digest(text)
    return path


def copy_shaders(dest_arg: str, source: Path | None = None) -> Path:
    """Copy the shader folder ``source`` (default: the one ``--shaders`` / ``$NATURA_SHADERS``
    / Natura's own resolve to) to a new folder ``dest_arg``: into a temporary sibling first,
    renamed at the end, so an error (full disk, Ctrl-C) leaves nothing and a retry works."""
    allowed = "allowed a new folder name in an existing, writable folder"
    if dest_arg is not None and not dest_arg.strip():
        raise UsageError(f"shaders copy DIR {quote(dest_arg)} is empty: allowed a new folder "
                         "name")
    dest = expand(dest_arg, "shaders copy DIR")
    shown = quote(str(dest))
    if os.path.lexists(dest):
        raise UsageError(f"{shown} already exists: "
                         "allowed a new folder name (nothing is overwritten)")
    parent = check_new_folder(dest, shown, allowed)
    source = Path(source) if source is not None else resolve_shader_root(None)
    tmp = temp_name_in(parent)
    _LIVE.add(tmp)
    try:
        shutil.copytree(source, tmp)
        if os.path.lexists(dest):  # taken while copying
            raise UsageError(f"{shown} already exists: "
                             "allowed a new folder name (nothing is overwritten)")
        os.rename(tmp, dest)
        _LIVE.discard(tmp)
    except (OSError, shutil.Error) as exc:
        why = exc.strerror if isinstance(exc, OSError) and exc.strerror else type(exc).__name__
        raise UsageError(f"cannot copy the shaders to {shown} ({why}): {allowed}, with free "
                         "space; nothing was left behind") from None
    finally:
        if tmp in _LIVE:
            _remove(tmp)
    return dest


def free_copy_name(folder: Path, stem: str = DEFAULT_COPY) -> str:
    """``my-glsl``, else ``my-glsl-2``, ``my-glsl-3``… : the first name not taken in
    ``folder`` (what the first save offers)."""
    if not os.path.lexists(Path(folder) / stem):
        return stem
    n = 2
    while os.path.lexists(Path(folder) / f"{stem}-{n}"):
        n += 1
    return f"{stem}-{n}"


def move_to_copy(library: ShaderLibrary, dest_arg: str) -> Path:
    """The first save of Natura's own shaders: copy them to ``dest_arg`` and move the running
    programs there (recompiled from the copy), so every later save edits the copy."""
    dest = copy_shaders(dest_arg, library.root)
    library.set_root(dest)
    return dest


def relocate(path: Path, old_root: Path, new_root: Path) -> Path:
    """The same file under another root (the editor's open file after a move to a copy)."""
    return Path(new_root) / Path(path).resolve().relative_to(Path(old_root).resolve())
