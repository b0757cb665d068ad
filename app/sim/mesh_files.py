"""A user's own mesh for the shading lab: OBJ, STL (ascii or binary), glTF and GLB files read
with trimesh into an ``app.sim.lab_meshes.LabMesh`` (numpy only, no GL).

* Scene graphs (a glTF with several nodes, an OBJ with several objects) are flattened: every
  node's geometry is put through its world transform (normals through the inverse transpose,
  the winding flipped under a mirroring transform) and the parts are concatenated.
* Normals the file carries (OBJ ``vn``, glTF ``NORMAL``) are kept; STL facet normals and files
  without normals get crease-angle normals (``app.sim.lab_meshes.from_arrays``: faceted across
  edges sharper than 30°). UVs the file carries are kept; without them, box-mapped planar UVs.
* Nothing is normalised silently: the mesh comes back in the file's own units and placement
  (``LabMesh.summary`` reports its bounds); :func:`fit` recentres it on the floor and scales it
  to a size, which the lab does on request.
* Nothing is downloaded: only the file and the buffers or images next to it are read (trimesh
  is called with ``allow_remote=False``).

Every failure is a :class:`MeshFileError`: one line naming the file and what is allowed
(``exit_code`` 2, like the other user errors of ``app.errors``).
"""

from __future__ import annotations

import json
import math
import os
from pathlib import Path
from typing import Any

import numpy as np

from ..errors import NaturaError, one_line, quote
from .lab_meshes import LabMesh, concatenate, from_arrays, transformed

#: file extensions load_mesh reads → trimesh's file type
EXTENSIONS = {".obj": "obj", ".stl": "stl", ".gltf": "gltf", ".glb": "glb"}
ALLOWED = ", ".join(EXTENSIONS)
#: the most triangles a loaded mesh may have (all nodes together)
MAX_TRIANGLES = 2_000_000
#: the largest mesh file read [bytes] (2 M triangles of OBJ text fit well under it)
MAX_BYTES = 512 * 2**20


class MeshFileError(NaturaError):
    """A mesh file that cannot be used: missing, a folder, unreadable, empty, too big or of an
    extension that is not allowed."""


def _fail(path: Path, what: str, allowed: str = f"allowed {ALLOWED}") -> MeshFileError:
    return MeshFileError(one_line(f"mesh file {quote(str(path))} {what}: {allowed}"))


def _reason(exc: BaseException) -> str:
    if isinstance(exc, json.JSONDecodeError):
        text = f"{exc.msg} at line {exc.lineno} column {exc.colno}"
    elif isinstance(exc, KeyError) and exc.args:  # a name the file refers to and does not hold
        text = f"missing {exc.args[0]}"
    elif isinstance(exc, ImportError):  # trimesh guessing a text encoding it cannot decode
        text = "not UTF-8 text"
    else:
        text = " ".join(str(exc).split()) or type(exc).__name__
    return text if len(text) <= 60 else text[:57] + "..."


def _binary_stl_triangles(path: Path) -> int | None:
    """The triangle count a binary STL's header claims, when the file's size matches it
    (None for an ascii STL or a size that does not match)."""
    try:
        size = path.stat().st_size
        with path.open("rb") as f:
            head = f.read(84)
    except OSError:
        return None
    if len(head) < 84:
        return None
    count = int(np.frombuffer(head[80:84], "<u4")[0])
    return count if size == 84 + 50 * count else None


def _check_path(path: Path) -> str:
    """The trimesh file type of ``path``, after refusing what cannot be a mesh file."""
    try:
        return _check_file(path)
    except OSError as exc:
        raise _fail(path, f"cannot be read ({_reason(exc)})",
                    f"allowed a readable {ALLOWED} file") from None


def _check_file(path: Path) -> str:
    ext = path.suffix.lower()
    if not path.exists():
        raise _fail(path, "does not exist", f"allowed an existing {ALLOWED} file")
    if path.is_dir():
        raise _fail(path, "is a folder", f"allowed a {ALLOWED} file")
    if not path.is_file():  # a pipe or a device would block the reader or never end
        raise _fail(path, "is not a regular file", f"allowed a {ALLOWED} file")
    if ext not in EXTENSIONS:
        shown = f"the extension {quote(ext)}" if ext else "no extension"
        raise _fail(path, f"has {shown}", f"allowed {ALLOWED}")
    if path.stat().st_size > MAX_BYTES:
        raise _fail(path, f"is {path.stat().st_size / 2**20:,.0f} MiB",
                    f"allowed at most {MAX_BYTES // 2**20} MiB")
    if not os.access(path, os.R_OK):
        raise _fail(path, "cannot be read (permission denied)", f"allowed a readable {ALLOWED} "
                    "file")
    if path.stat().st_size == 0:
        raise _fail(path, "is empty", f"allowed a {ALLOWED} file with triangles")
    if ext in (".obj", ".gltf"):
        with path.open("rb") as f:
            head = f.read(1 << 16)
        if b"\x00" in head:
            raise _fail(path, f"is binary data, not {ext[1:].upper()} text",
                        f"allowed valid {ALLOWED} files")
    if ext == ".gltf":
        try:
            json.loads(path.read_bytes())
        except (ValueError, UnicodeDecodeError) as exc:
            raise _fail(path, f"is not glTF JSON ({_reason(exc)})",
                        f"allowed valid {ALLOWED} files") from None
    if ext == ".stl":
        claimed = _binary_stl_triangles(path)
        if claimed is not None and claimed > MAX_TRIANGLES:
            raise _fail(path, f"has {claimed:,} triangles", f"allowed at most {MAX_TRIANGLES:,}")
    return EXTENSIONS[ext]


def _has_normals(geometry: Any) -> bool:
    """Whether the file gave this geometry vertex normals (trimesh caches them only then; its
    ``vertex_normals`` property would otherwise compute smooth ones)."""
    cache = getattr(geometry, "_cache", None)
    try:
        return cache is not None and "vertex_normals" in cache
    except TypeError:
        return False


def _uvs(geometry: Any, count: int) -> np.ndarray | None:
    uv = getattr(getattr(geometry, "visual", None), "uv", None)
    if uv is None:
        return None
    uv = np.asarray(uv, np.float64)
    if uv.shape != (count, 2) or not np.isfinite(uv).all():
        return None
    return uv


def _part(name: str, geometry: Any, transform: np.ndarray) -> LabMesh | None:
    """One node's geometry in the file's world frame (None when it has no triangles)."""
    faces = np.asarray(getattr(geometry, "faces", np.zeros((0, 3))), np.int64).reshape(-1, 3)
    if len(faces) == 0:
        return None
    vertices = np.asarray(geometry.vertices, np.float64)
    m = np.asarray(transform, np.float64)[:3, :3]
    positions = vertices @ m.T + np.asarray(transform, np.float64)[:3, 3]
    normals = None
    if _has_normals(geometry):
        n = np.asarray(geometry.vertex_normals, np.float64)
        if n.shape == vertices.shape:
            try:
                normals = n @ np.linalg.inv(m)  # the inverse transpose, applied to rows
            except np.linalg.LinAlgError:
                normals = None
    if np.linalg.det(m) < 0:  # a mirroring transform turns the triangles inside out
        faces = faces[:, [0, 2, 1]]
    uvs = _uvs(geometry, len(vertices))
    if normals is None and uvs is None:
        # vertices only told apart by position: weld them (STL repeats each corner)
        key = np.ascontiguousarray(positions.astype(np.float32) + np.float32(0.0))
        _, first, inverse = np.unique(key, axis=0, return_index=True, return_inverse=True)
        positions = positions[first]
        faces = inverse.reshape(-1)[faces]
    return from_arrays(name, positions, faces, normals=normals, uvs=uvs)


def load_mesh(path: str | os.PathLike[str]) -> LabMesh:
    """The mesh in ``path`` (.obj, .stl, .gltf, .glb) as a :class:`LabMesh` named after the
    file, every node flattened with its transform, in the file's own units (see :func:`fit`).
    Raises :class:`MeshFileError` (one line) for anything that cannot be used."""
    path = Path(path)
    file_type = _check_path(path)
    try:
        import trimesh
    except ImportError:
        raise MeshFileError(one_line(
            f"mesh file {quote(str(path))} needs the trimesh package to be read: allowed "
            "after pip install 'trimesh>=4'")) from None
    try:
        scene = trimesh.load_scene(str(path), file_type=file_type, allow_remote=False,
                                   process=False)
    except MemoryError:
        raise _fail(path, "is too big to read", f"allowed at most {MAX_TRIANGLES:,} "
                    "triangles") from None
    except Exception as exc:  # trimesh raises many kinds on a broken file
        raise _fail(path, f"is not a readable {file_type.upper()} file ({_reason(exc)})",
                    f"allowed valid {ALLOWED} files") from None

    nodes = []
    try:
        for node in scene.graph.nodes_geometry:
            transform, geometry_name = scene.graph[node]
            geometry = scene.geometry.get(geometry_name)
            if geometry is not None and len(getattr(geometry, "faces", ())) > 0:
                nodes.append((transform, geometry))
    except Exception as exc:
        raise _fail(path, f"has a scene graph that cannot be flattened ({_reason(exc)})",
                    f"allowed valid {ALLOWED} files") from None
    total = sum(len(g.faces) for _, g in nodes)
    if total == 0:
        raise _fail(path, "has no triangles (only points, lines or nothing)",
                    f"allowed meshes of 1 to {MAX_TRIANGLES:,} triangles")
    if total > MAX_TRIANGLES:
        raise _fail(path, f"has {total:,} triangles", f"allowed at most {MAX_TRIANGLES:,}")

    name = path.stem or "mesh"
    try:
        parts = [p for t, g in nodes if (p := _part(name, g, t)) is not None]
    except (ValueError, IndexError) as exc:
        raise _fail(path, f"has broken geometry ({_reason(exc)})",
                    f"allowed valid {ALLOWED} files") from None
    return parts[0] if len(parts) == 1 else concatenate(name, parts)


def fit(mesh: LabMesh, size: float = 1.5) -> LabMesh:
    """``mesh`` scaled uniformly so that its largest extent is ``size`` metres, centred on the
    y axis and resting on y = 0 (a mesh of zero extent is only moved). The lab does this to a
    loaded mesh; nothing else rescales."""
    if not (isinstance(size, (int, float)) and math.isfinite(size) and size > 0):
        raise ValueError(f"fit size {size!r} is not allowed: allowed a finite size > 0 (m)")
    lo, hi = mesh.bounds()
    extent = float(np.max(hi - lo)) if mesh.vertex_count else 0.0
    scale = size / extent if extent > 0 else 1.0
    centre = (lo + hi) / 2
    offset = np.array([-centre[0], -lo[1], -centre[2]]) * scale
    return transformed(mesh, scale, offset)
