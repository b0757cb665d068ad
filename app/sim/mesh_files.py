"""A user's own mesh for the shading lab: OBJ, STL (ascii or binary), glTF and GLB files read
into an ``app.sim.lab_meshes.LabMesh`` (numpy only, no GL).

* OBJ text and STL are read with numpy (``app.sim.mesh_formats``: a 2,000,000-triangle file in
  seconds); glTF and GLB with trimesh, after their layout is checked, handed only their
  geometry (materials emptied; images, textures, cameras, skins and animations left out).
* Scene graphs (a glTF with several nodes) are flattened: every node's geometry is put through
  its world transform (normals through the inverse transpose, the winding flipped under a
  mirroring transform) and the parts are concatenated. An OBJ's objects, groups and materials
  are one mesh.
* Normals the file carries (OBJ ``vn``, glTF ``NORMAL``) are kept; STL facet normals and files
  without normals get crease-angle normals (``app.sim.lab_meshes.from_arrays``: faceted across
  edges sharper than 30°). UVs the file carries are kept; without them, box-mapped planar UVs.
* Nothing is normalised silently: the mesh comes back in the file's own units and placement
  (``LabMesh.summary`` reports its bounds); :func:`fit` recentres it on the floor and scales it
  to a size, which the lab does on request.
* Nothing is downloaded: only the file and the buffers next to it are read (a buffer at a URL
  is refused; trimesh is called with ``allow_remote=False``).

What is refused rather than guessed at (a user expects to see their mesh, or to be told why
not):

* a coordinate (after the node transforms) or texture coordinate that is not finite or lies
  beyond float32 (|x| > 3.4e38): the GPU could not hold it;
* an OBJ face index of 0 or beyond the ``v``/``vt``/``vn`` entries that exist, a zero or
  non-finite ``vn`` a face uses (``app.sim.mesh_formats.read_obj``, naming the line); a glTF
  ``NORMAL`` of zero length is not refused but replaced by a crease normal, as exporters write
  such normals on collapsed faces;
* a mesh whose triangles all have zero area (nothing would be drawn). Some degenerate
  triangles among good ones are kept and draw nothing (CAD exports often have a few);
* a binary STL whose header's triangle count does not match its size; a glTF whose JSON
  nests more than 100 levels or whose arrays, indices, buffers and accessors do not fit
  together (``app.sim.mesh_formats.check_gltf``).

Every failure is a :class:`MeshFileError`: one line naming the file and what is allowed
(``exit_code`` 2, like the other user errors of ``app.errors``).
"""

from __future__ import annotations

import contextlib
import io
import json
import logging
import math
import os
import warnings
from pathlib import Path
from typing import Any, Iterator

import numpy as np

from ..errors import NaturaError, one_line, quote
from .lab_meshes import LabMesh, _face_normals, concatenate, from_arrays, transformed, unique_rows
from .mesh_formats import (
    COORD_ALLOWED,
    COORD_LIMIT,
    Geometry,
    Problem,
    check_gltf,
    geometry_only,
    glb_chunks,
    glb_container,
    json_document,
    read_ascii_stl,
    read_binary_stl,
    read_obj,
    stl_layout,
)

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


def _check_path(path: Path) -> str:
    """The file type of ``path`` (its extension without the dot), after refusing what cannot
    be a mesh file."""
    try:
        return _check_file(path)
    except OSError as exc:
        reason = exc.strerror or "an operating-system error"
        raise _fail(path, f"cannot be read ({reason})",
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
    return EXTENSIONS[ext]


@contextlib.contextmanager
def _quiet() -> Iterator[None]:
    """trimesh's log lines and numpy's floating-point warnings held back: what they would
    report is checked afterwards and refused in one line."""
    log = logging.getLogger("trimesh")
    level = log.level
    log.setLevel(logging.CRITICAL + 1)
    try:
        with warnings.catch_warnings(), np.errstate(all="ignore"):
            warnings.simplefilter("ignore")
            yield
    finally:
        log.setLevel(level)


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


def _placed(geometry: Any, transform: np.ndarray) -> Geometry:
    """One trimesh geometry in the file's world frame."""
    faces = np.asarray(getattr(geometry, "faces", np.zeros((0, 3))), np.int64).reshape(-1, 3)
    vertices = np.asarray(geometry.vertices, np.float64).reshape(-1, 3)
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
    return Geometry(positions=positions, faces=faces, normals=normals,
                    uvs=_uvs(geometry, len(vertices)),
                    moved=not np.array_equal(transform, np.eye(4)))


def _with_trimesh(path: Path, file_type: str, data: bytes | None = None) -> list[Geometry]:
    """Every node's triangles in ``path`` (or in ``data``, what it holds as trimesh should
    read it, with buffers next to ``path``) read by trimesh, in the file's world frame."""
    try:
        import trimesh
    except ImportError:
        raise MeshFileError(one_line(
            f"mesh file {quote(str(path))} needs the trimesh package to be read: allowed "
            "after pip install 'trimesh>=4'")) from None
    kind = file_type.upper()
    with _quiet():
        try:
            source = str(path) if data is None else io.BytesIO(data)
            resolver = trimesh.resolvers.FilePathResolver(str(path))
            scene = trimesh.load_scene(source, file_type=file_type, resolver=resolver,
                                       allow_remote=False, process=False)
        except MemoryError:
            raise _fail(path, "is too big to read", f"allowed at most {MAX_TRIANGLES:,} "
                        "triangles") from None
        except RecursionError:
            raise _fail(path, f"is not a readable {kind} file (it nests too deeply)",
                        f"allowed valid {ALLOWED} files") from None
        except Exception:  # trimesh raises many kinds on a broken file
            raise _fail(path, f"is not a readable {kind} file (its content does not follow "
                        "the format)", f"allowed valid {ALLOWED} files") from None
        parts = []
        try:
            for node in scene.graph.nodes_geometry:
                transform, geometry_name = scene.graph[node]
                geometry = scene.geometry.get(geometry_name)
                if geometry is not None and len(getattr(geometry, "faces", ())) > 0:
                    parts.append(_placed(geometry, transform))
        except Exception:
            raise _fail(path, "has a scene graph that cannot be flattened",
                        f"allowed valid {ALLOWED} files") from None
    return parts


def _read_stl(path: Path) -> list[Geometry]:
    with path.open("rb") as f:
        head = f.read(1 << 16)
    count = stl_layout(head, path.stat().st_size)
    if count is None:
        return read_ascii_stl(path.read_bytes(), MAX_TRIANGLES)
    if count > MAX_TRIANGLES:
        raise Problem(f"has {count:,} triangles", f"allowed at most {MAX_TRIANGLES:,}")
    return [read_binary_stl(path.read_bytes(), count)]


def _read_gltf(path: Path, file_type: str) -> list[Geometry]:
    data = path.read_bytes()
    if file_type == "glb":
        text, binary = glb_chunks(data)
    else:
        text, binary = data, None
    doc = json_document(text)
    check_gltf(doc, binary, path.parent)
    doc = geometry_only(doc)
    data = glb_container(doc, binary) if file_type == "glb" else json.dumps(doc).encode()
    return _with_trimesh(path, file_type, data)


def _checked(parts: list[Geometry]) -> list[Geometry]:
    """The parts with triangles, after refusing a mesh with none or too many, an index
    pointing at no vertex, a coordinate beyond float32, or nothing but degenerate triangles."""
    parts = [g for g in parts if len(g.faces)]
    total = sum(len(g.faces) for g in parts)
    if total == 0:
        raise Problem("has no triangles (only points, lines or nothing)",
                      f"allowed meshes of 1 to {MAX_TRIANGLES:,} triangles")
    if total > MAX_TRIANGLES:
        raise Problem(f"has {total:,} triangles", f"allowed at most {MAX_TRIANGLES:,}")
    base = 0
    visible = False
    for g in parts:
        count = len(g.positions)
        if g.faces.min() < 0 or g.faces.max() >= count:
            bad = int(g.faces.max() if g.faces.max() >= count else g.faces.min())
            raise Problem(f"has a triangle using vertex {bad:,} of {count:,}",
                          f"allowed vertex indices 0 to {count - 1:,}")
        bad = ~(np.abs(g.positions) <= COORD_LIMIT)  # NaN and infinity too
        if bad.any():
            row, col = np.argwhere(bad)[0]
            value = float(g.positions[row, col])
            where = " (after its node transforms)" if g.moved else ""
            raise Problem(f"has the coordinate {value:g} at vertex {base + row + 1:,}{where}",
                          COORD_ALLOWED)
        base += count
        visible = visible or _any_area(g.positions, g.faces)
    if not visible:
        which = f"all {total:,} have" if total > 1 else "its one triangle has"
        raise Problem(f"has only degenerate triangles ({which} zero area)",
                      "allowed at least one triangle of non-zero area")
    return parts


def _any_area(positions: np.ndarray, faces: np.ndarray, chunk: int = 1 << 16) -> bool:
    """Whether any triangle has an area (``from_arrays``'s test), looking a chunk at a time:
    a mesh worth drawing answers in its first."""
    return any(_face_normals(positions, faces[i:i + chunk])[1].any()
               for i in range(0, len(faces), chunk))


def _lab_mesh(name: str, g: Geometry) -> LabMesh:
    positions, faces = g.positions, g.faces
    welded = g.normals is None and g.uvs is None
    if welded:
        # vertices only told apart by position: weld them (STL repeats each corner)
        first, inverse = unique_rows(positions.astype(np.float32) + np.float32(0.0))
        positions = np.take(positions, first, axis=0)  # as positions[first], faster
        faces = np.take(inverse, faces)
    return from_arrays(name, positions, faces, normals=g.normals, uvs=g.uvs, welded=welded)


def load_mesh(path: str | os.PathLike[str]) -> LabMesh:
    """The mesh in ``path`` (.obj, .stl, .gltf, .glb) as a :class:`LabMesh` named after the
    file, every node flattened with its transform, in the file's own units (see :func:`fit`).
    Raises :class:`MeshFileError` (one line) for anything that cannot be used (the module's
    docstring)."""
    path = Path(path)
    file_type = _check_path(path)
    name = path.stem or "mesh"
    try:
        if file_type == "obj":
            parts = [read_obj(path.read_bytes(), MAX_TRIANGLES)]
        elif file_type == "stl":
            parts = _read_stl(path)
        else:
            parts = _read_gltf(path, file_type)
        meshes = [_lab_mesh(name, g) for g in _checked(parts)]
    except Problem as problem:
        raise _fail(path, problem.what, problem.allowed) from None
    except MemoryError:
        raise _fail(path, "is too big to read", f"allowed at most {MAX_TRIANGLES:,} "
                    "triangles") from None
    except OSError as exc:
        raise _fail(path, f"cannot be read ({exc.strerror or 'an operating-system error'})",
                    f"allowed a readable {ALLOWED} file") from None
    except ValueError as exc:  # from_arrays: our own one-line words
        raise _fail(path, f"has broken geometry ({exc})", f"allowed valid {ALLOWED} files"
                    ) from None
    return meshes[0] if len(meshes) == 1 else concatenate(name, meshes)


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
