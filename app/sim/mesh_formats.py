"""The parts of reading a mesh file that ``app.sim.mesh_files`` does itself, with numpy, rather
than through trimesh: faster on big files and strict where trimesh is lenient.

* :func:`read_obj` — Wavefront OBJ text: ``v``, ``vt``, ``vn`` and ``f`` (any polygon, fanned
  into triangles; ``v``, ``v/vt``, ``v/vt/vn`` and ``v//vn`` corners; negative indices count
  back from the statement). Every other statement (``o``, ``g``, ``s``, ``usemtl``, ``mtllib``,
  ``l``, ``p``, free-form geometry) and ``#`` comments are skipped; the whole file is one mesh.
  What a face uses is checked, with its line: an index of 0 or beyond the vertices, normals or
  texture coordinates that exist, a coordinate that is not finite or beyond float32, a normal
  of zero length. Unused vertices are ignored, as trimesh does.
* :func:`stl_layout`, :func:`read_binary_stl` and :func:`read_ascii_stl` — binary STL, 50
  bytes a triangle read in one pass, and ASCII STL, three ``vertex`` lines a facet (the facet
  normals are ignored: ``from_arrays`` makes crease normals).
* :func:`glb_chunks`, :func:`json_document` and :func:`check_gltf` — a glTF document's layout
  checked before trimesh reads its buffers: the arrays, indices, buffer, bufferView and accessor
  extents, the node tree, so that a broken file is named in words instead of failing inside
  trimesh; :func:`geometry_only` and :func:`glb_container` — what trimesh is then handed.

Each problem is a :class:`Problem` (what is wrong, what is allowed); ``mesh_files`` adds the
file's name to make it one line.
"""

from __future__ import annotations

import base64
import binascii
import json
import math
import re
import urllib.parse
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Callable

import numpy as np

from .lab_meshes import unique_rows

#: the largest coordinate magnitude accepted: float32's largest finite value (3.4028235e38),
#: since positions and texture coordinates reach the GPU as float32
COORD_LIMIT = float(np.finfo(np.float32).max)
COORD_ALLOWED = "allowed finite numbers within ±3.4e38 (float32)"
#: how deep a glTF's JSON may nest (a glTF needs about 8 levels; extras may add some)
MAX_JSON_DEPTH = 100
#: a normal shorter than this counts as zero (as app.sim.lab_meshes does)
_NORMAL_EPS = 1e-12


class Problem(Exception):
    """What is wrong with a mesh file and what is allowed instead (the file is named by the
    caller)."""

    def __init__(self, what: str, allowed: str) -> None:
        super().__init__(f"{what}: {allowed}")
        self.what = what
        self.allowed = allowed


@dataclass
class Geometry:
    """Triangles read from a file, in its own frame: positions (V, 3) float64, faces (T, 3)
    int64 and, when the file gives them, normals (V, 3) (a zero row: none for that vertex) and
    uvs (V, 2)."""

    positions: np.ndarray
    faces: np.ndarray
    normals: np.ndarray | None = None
    uvs: np.ndarray | None = None
    #: whether a node's transform placed them (a coordinate out of range says so)
    moved: bool = False



class _Tokens:
    """The whitespace-separated tokens of a text as (start, end) byte offsets, with the line
    (1-based, as an editor counts) each one is on."""

    def __init__(self, data: bytes) -> None:
        # line ends as an editor sees them, without moving a byte: CR LF → " LF", lone CR → LF
        if b"\r" in data:
            data = data.replace(b"\r\n", b" \n").replace(b"\r", b"\n")
        text = np.frombuffer(data, np.uint8)
        self.newlines = np.flatnonzero(text == 10)
        ends = self.newlines
        # a backslash before a line end joins the next line to this one (OBJ's continuation)
        if b"\\\n" in data:
            text = np.frombuffer(data.replace(b"\\\n", b"  "), np.uint8)
            ends = np.flatnonzero(text == 10)
        self.text = text
        padded = np.ones(len(text) + 2, bool)
        np.less_equal(text, 32, out=padded[1:-1])  # whitespace and control characters
        edges = np.flatnonzero(padded[1:] != padded[:-1])
        if len(text) < 2**31:  # half the memory for a big file's tens of millions of tokens
            edges = edges.astype(np.int32)
        self.starts, self.ends = edges[0::2], edges[1::2]
        # whether each token starts a statement: the first after a line end
        first = np.zeros(len(self.starts) + 1, bool)
        first[0] = True
        first[np.searchsorted(self.starts, ends)] = True
        self.first = first[:-1]

    def line(self, token: int) -> int:
        return int(np.searchsorted(self.newlines, self.starts[token])) + 1

    def word(self, token: int, limit: int = 30) -> str:
        raw = bytes(self.text[self.starts[token]:self.ends[token]]).decode("latin-1")
        return raw if len(raw) <= limit else raw[:limit - 1] + "…"

    def numbers(self, tokens: np.ndarray, dtype: type, what: str | Callable[[int], str]
                ) -> np.ndarray:
        """The tokens ``tokens`` (indices, in order) read as numbers of ``dtype``; a token that
        is not a number is a :class:`Problem` naming it, its line and ``what`` belongs there
        (a text, or a function of the token)."""
        if len(tokens) == 0:
            return np.zeros(0, dtype)
        mark = np.zeros(len(self.text) + 1, np.int8)
        mark[self.starts[tokens]] = 1
        mark[self.ends[tokens]] = -1
        inside = np.cumsum(mark[:-1], dtype=np.int8).view(bool)
        buf = np.where(inside, self.text, np.uint8(32)).tobytes()
        try:
            out: np.ndarray = np.fromstring(buf, dtype=dtype, sep=" ")
        except ValueError:
            out = np.zeros(0, dtype)
        if len(out) == len(tokens):
            return out
        for t in tokens:  # find the culprit (only when there is one)
            raw = bytes(self.text[self.starts[t]:self.ends[t]])
            try:
                ok = len(np.fromstring(raw, dtype=dtype, sep=" ")) == 1
            except ValueError:
                ok = False
            if not ok:
                kind = "an integer" if dtype is np.int64 else "a number"
                name = what if isinstance(what, str) else what(int(t))
                raise Problem(f"has {self.word(t)!r} at line {self.line(t)} where {name} "
                              "belongs", f"allowed {kind} there")
        raise Problem("has numbers that cannot be read", "allowed plain decimal numbers")


def _many(count: int, one: str, more: str = "") -> str:
    return f"{count} {one}" if count == 1 else f"{count} {more or one + 's'}"


def _shown_number(value: float) -> str:
    return f"{value:g}"  # 1e+39, inf, nan


def _heads(first: np.ndarray) -> np.ndarray:
    """The index of the first token of each token's statement."""
    index = np.arange(len(first), dtype=np.int32 if len(first) < 2**31 else np.int64)
    return np.maximum.accumulate(np.where(first, index, 0))


def _statements(tok: _Tokens) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(kind of each token's statement: 1 v, 2 vt, 3 vn, 4 f, 0 anything else (skipped);
    whether it is the keyword; its statement's keyword token), after dropping ``#`` comments
    (from a token starting with # to the line's end)."""
    t = tok.text
    n = len(t)
    head = _heads(tok.first)
    comment = t[tok.starts] == ord("#")
    seen = np.cumsum(comment)
    keep = seen - seen[head] + comment[head] == 0
    tok.starts, tok.ends, tok.first = tok.starts[keep], tok.ends[keep], tok.first[keep]
    first = tok.first
    length = tok.ends - tok.starts
    c0 = t[tok.starts]
    c1 = t[np.minimum(tok.starts + 1, n - 1)]
    kind = np.zeros(len(tok.starts), np.int8)
    kind[(length == 1) & (c0 == ord("v"))] = 1
    kind[(length == 2) & (c0 == ord("v")) & (c1 == ord("t"))] = 2
    kind[(length == 2) & (c0 == ord("v")) & (c1 == ord("n"))] = 3
    kind[(length == 1) & (c0 == ord("f"))] = 4
    kind[~first] = 0
    head = _heads(first)
    return kind[head], first, head


def _records(kinds: np.ndarray, first: np.ndarray, head: np.ndarray, code: int):
    """The statements of one kind: (keyword token of each, its data tokens, the statement each
    data token belongs to (0-based among these), how many data tokens each has)."""
    mine = kinds == code
    keys = np.flatnonzero(mine & first)
    data = np.flatnonzero(mine & ~first)
    ordinal = np.zeros(len(first), np.int64)
    ordinal[keys] = np.arange(len(keys))
    owner = ordinal[head[data]]
    return keys, data, owner, np.bincount(owner, minlength=len(keys))


def _leading(data: np.ndarray, owner: np.ndarray, counts: np.ndarray, width: int
             ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The first ``width`` data tokens of each statement: (tokens, their statement, column)."""
    begin = np.concatenate(([0], np.cumsum(counts)[:-1]))
    column = np.arange(len(data)) - begin[owner]
    take = column < width
    return data[take], owner[take], column[take]


@dataclass
class _Columns:
    """What to read of one kind of statement: the statements ``rows`` of a :func:`_records`
    ``record``, ``width`` numbers of each (missing ones 0), each having at least ``least``."""

    record: tuple
    rows: np.ndarray
    width: int
    least: int
    name: str
    usage: str


def _vectors(tok: _Tokens, wanted: list[_Columns]) -> list[np.ndarray]:
    """(len(rows), width) floats for each of ``wanted``, every token read in one pass."""
    chosen_all = np.zeros(len(tok.starts), np.int8)
    placed = []
    for i, w in enumerate(wanted):
        keys, data, owner, counts = w.record
        keys = keys[w.rows]
        data, owner, counts = _subset(data, owner, counts, w.rows)
        short = np.flatnonzero(counts < w.least)
        if len(short):
            k = keys[short[0]]
            raise Problem(f"has a {w.name} of {_many(counts[short[0]], 'number')} at line "
                          f"{tok.line(k)}", f"allowed {w.usage}")
        chosen, row, column = _leading(data, owner, counts, w.width)
        chosen_all[chosen] = i + 1
        placed.append((row, column))
    tokens = np.flatnonzero(chosen_all)
    which = chosen_all[tokens]
    values = tok.numbers(tokens, np.float64,
                         lambda t: f"a {wanted[chosen_all[t] - 1].name} number")
    out = []
    for i, (w, (row, column)) in enumerate(zip(wanted, placed)):
        block = np.zeros((len(w.rows), w.width))
        block[row, column] = values[which == i + 1]  # in the text's order, as row, column
        out.append(block)
    return out


def _resolve(index: np.ndarray, keys: np.ndarray, tok: _Tokens, corners: np.ndarray,
             name: str) -> np.ndarray:
    """0-based indices from OBJ's 1-based ones, or negative ones counting back from the
    statement (``keys``: the tokens of the statements pointed at); the first that points at
    nothing is a :class:`Problem`."""
    total = len(keys)
    back = index < 0
    out = index - 1
    if back.any():
        out[back] = np.searchsorted(keys, corners[back]) + index[back]
    bad = (index == 0) | (out >= total) | (out < 0)
    if bad.any():
        i = int(np.argmax(bad))
        before = int(np.searchsorted(keys, corners[i]))
        allowed = (f"allowed 1 to {total:,}" if total else f"allowed none: the file has no {name}"
                   " entries") + (f", or -1 to -{before:,} counting back" if before else "")
        shown = (f"{int(index[i])}" if abs(int(index[i])) < 2**62 else
                 f"in {tok.word(corners[i])!r}")  # a number too big for 64 bits
        raise Problem(f"has {name} index {shown} at line {tok.line(corners[i])}",
                      allowed + (" (OBJ counts from 1)" if total else ""))
    return out


def _limit(triangles: int, most: int | None) -> None:
    if most is not None and triangles > most:
        raise Problem(f"has {triangles:,} triangles", f"allowed at most {most:,}")


def read_obj(data: bytes, max_triangles: int | None = None) -> Geometry:
    """The triangles of OBJ text (see the module's docstring); a :class:`Problem` for anything
    broken that a face uses, or for more than ``max_triangles``."""
    tok = _Tokens(data)
    kinds, first, head = _statements(tok)
    v_record = _records(kinds, first, head, 1)
    vt_record = _records(kinds, first, head, 2)
    vn_record = _records(kinds, first, head, 3)
    v_keys, vt_keys, vn_keys = v_record[0], vt_record[0], vn_record[0]
    f_keys, corners, f_owner, f_counts = _records(kinds, first, head, 4)

    if len(f_keys) == 0:  # points, lines or nothing: the caller says so
        return Geometry(positions=np.zeros((0, 3)), faces=np.zeros((0, 3), np.int64))
    few = np.flatnonzero(f_counts < 3)
    if len(few):
        k = f_keys[few[0]]
        raise Problem(f"has a face of {_many(f_counts[few[0]], 'corner')} at line {tok.line(k)}",
                      "allowed faces of 3 or more corners")
    _limit(int(f_counts.sum()) - 2 * len(f_counts), max_triangles)
    # the corners' forms: v, v/vt, v/vt/vn or v//vn
    t = tok.text
    cs, ce = tok.starts[corners], tok.ends[corners]
    slashes = np.flatnonzero(t == ord("/"))
    at = np.searchsorted(cs, slashes, side="right") - 1
    inside = (at >= 0) & (slashes < ce[np.maximum(at, 0)])
    slashes, at = slashes[inside], at[inside]
    count = np.bincount(at, minlength=len(corners))
    double = np.bincount(at[t[np.minimum(slashes + 1, len(t) - 1)] == ord("/")],
                         minlength=len(corners))
    edge_slash = (t[cs] == ord("/")) | (t[ce - 1] == ord("/"))
    good = ~edge_slash & (((count <= 2) & (double == 0)) | ((count == 2) & (double == 1)))
    if not good.all():
        c = corners[int(np.argmin(good))]
        raise Problem(f"has the face corner {tok.word(c)!r} at line {tok.line(c)}",
                      "allowed v, v/vt, v/vt/vn or v//vn with integers")
    has_t = (count >= 1) & (double == 0)
    has_n = count == 2
    # the integers of every corner, '/' read as a space
    width = count + 1 - double
    numbers = _corner_numbers(tok, corners, width)
    offset = np.concatenate(([0], np.cumsum(width)[:-1]))
    vi = numbers[offset]
    ti = np.where(has_t, numbers[np.minimum(offset + 1, len(numbers) - 1)], 0)
    ni = np.where(has_n, numbers[np.minimum(offset + width - 1, len(numbers) - 1)], 0)

    vi = _resolve(vi, v_keys, tok, corners, "vertex")
    # texture coordinates are used when every corner has one (else box mapping), but every
    # index given is checked
    use_uv = bool(has_t.all())
    if has_t.any():
        pick = np.flatnonzero(has_t)
        ti[pick] = _resolve(ti[pick], vt_keys, tok, corners[pick], "texture")
    if has_n.any():
        pick = np.flatnonzero(has_n)
        ni_used = _resolve(ni[pick], vn_keys, tok, corners[pick], "normal")
        ni = np.full(len(corners), -1, np.int64)
        ni[pick] = ni_used

    # the vertices, texture coordinates and normals the faces use, read and checked
    used_v = _used(vi, len(v_keys))
    wanted = [_Columns(v_record, used_v, 3, 3, "vertex", "'v x y z' (3 numbers or more)")]
    if use_uv:
        used_t = _used(ti, len(vt_keys))
        wanted.append(_Columns(vt_record, used_t, 2, 1, "texture coordinate",
                               "'vt u [v [w]]' (1 to 3 numbers)"))
    if has_n.any():
        used_n = _used(ni[ni >= 0], len(vn_keys))
        wanted.append(_Columns(vn_record, used_n, 3, 3, "normal", "'vn x y z' (3 numbers)"))
    values = _vectors(tok, wanted)
    positions = np.zeros((len(v_keys), 3))
    positions[used_v] = values[0]
    _check_range(tok, positions[used_v], v_keys[used_v], "coordinate")
    columns = [vi]
    uvs = normals = None
    if use_uv:
        uvs = np.zeros((len(vt_keys), 2))
        uvs[used_t] = values[1]
        _check_range(tok, uvs[used_t], vt_keys[used_t], "texture coordinate")
        columns.append(ti)
    if has_n.any():
        normals = np.zeros((len(vn_keys) + 1, 3))  # the last row: no normal (-1)
        normals[used_n] = values[-1]
        _check_normals(tok, normals[used_n], vn_keys[used_n])
        columns.append(ni)

    # one vertex per distinct (v, vt, vn) a corner uses; the faces fanned into triangles
    triangles = _fan(f_counts)
    if len(columns) == 1:  # positions only: the vertices used, in the file's order
        renumber = np.zeros(len(v_keys), np.int64)
        renumber[used_v] = np.arange(len(used_v))
        return Geometry(positions=positions[used_v], faces=renumber[vi][triangles])
    first_corner, inverse = unique_rows(np.stack(columns, axis=1))
    return Geometry(positions=positions[vi[first_corner]], faces=inverse[triangles],
                    normals=None if normals is None else normals[ni[first_corner]],
                    uvs=None if uvs is None else uvs[ti[first_corner]])


def _used(index: np.ndarray, count: int) -> np.ndarray:
    """The distinct values of ``index`` (all in 0…count − 1), sorted."""
    seen = np.zeros(count, bool)
    seen[index] = True
    return np.flatnonzero(seen)


def _subset(data: np.ndarray, owner: np.ndarray, counts: np.ndarray, rows: np.ndarray):
    """The data tokens of statements ``rows`` only: (data, owner renumbered, counts)."""
    keep = np.zeros(len(counts), bool)
    keep[rows] = True
    take = keep[owner]
    renumber = np.cumsum(keep) - 1
    return data[take], renumber[owner[take]], counts[rows]


def _corner_numbers(tok: _Tokens, corners: np.ndarray, width: np.ndarray) -> np.ndarray:
    """The integers of the face corners in order ('/' and '//' separate them)."""
    if len(corners) == 0:
        return np.zeros(0, np.int64)
    t = tok.text
    mark = np.zeros(len(t) + 1, np.int8)
    mark[tok.starts[corners]] = 1
    mark[tok.ends[corners]] = -1
    inside = np.cumsum(mark[:-1], dtype=np.int8).view(bool)
    keep = inside & (t != ord("/"))
    buf = np.where(keep, t, np.uint8(32)).tobytes()
    expected = int(width.sum())
    try:
        out = np.fromstring(buf, dtype=np.int64, sep=" ")
    except ValueError:
        out = np.zeros(0, np.int64)
    if len(out) == expected:
        return out
    for c in corners:
        parts = bytes(t[tok.starts[c]:tok.ends[c]]).split(b"/")
        if not all(re.fullmatch(rb"[+-]?\d{1,18}", p) for p in parts if p):
            raise Problem(f"has the face corner {tok.word(c)!r} at line {tok.line(c)}",
                          "allowed v, v/vt, v/vt/vn or v//vn with integers")
    raise Problem("has face indices that cannot be read", "allowed integers")


def _check_range(tok: _Tokens, values: np.ndarray, keys: np.ndarray, name: str) -> None:
    bad = ~(np.abs(values) <= COORD_LIMIT)  # NaN and infinity too
    if bad.any():
        row, col = np.argwhere(bad)[0]
        raise Problem(f"has the {name} {_shown_number(float(values[row, col]))} at line "
                      f"{tok.line(keys[row])}", COORD_ALLOWED)


def _check_normals(tok: _Tokens, normals: np.ndarray, keys: np.ndarray) -> None:
    with np.errstate(over="ignore", invalid="ignore"):
        length = np.sqrt(np.einsum("ij,ij->i", normals, normals))
    bad = ~np.isfinite(normals).all(axis=1) | ~(length > _NORMAL_EPS)
    if bad.any():
        row = int(np.argmax(bad))
        shown = ", ".join(_shown_number(float(x)) for x in normals[row])
        raise Problem(f"has the normal ({shown}) at line {tok.line(keys[row])}, used by a "
                      "face", "allowed finite normals of non-zero length")


def _fan(counts: np.ndarray) -> np.ndarray:
    """(T, 3) corner indices of polygons of ``counts`` corners (stored one after the other):
    a quad a b c d as (a, b, c) and (c, d, a), a larger polygon fanned from its first corner
    (as trimesh reads them)."""
    per = counts - 2
    first = np.concatenate(([0], np.cumsum(counts)[:-1]))
    face = np.repeat(np.arange(len(counts)), per)
    j = np.arange(int(per.sum())) - np.repeat(np.cumsum(per) - per, per)
    a = first[face]
    out = np.stack([a, a + j + 1, a + j + 2], axis=1)
    second = (counts[face] == 4) & (j == 1)
    out[second] = out[second][:, [1, 2, 0]]
    if len(counts) and (counts == 4).all():  # all quads: every first half, then the second
        out = np.concatenate([out[0::2], out[1::2]])
    return out


STL_HEADER = 84
STL_RECORD = np.dtype([("normal", "<f4", (3,)), ("vertices", "<f4", (3, 3)), ("attr", "<u2")])


def stl_layout(head: bytes, size: int) -> int | None:
    """The triangle count of a binary STL (its header count, checked against the file's size),
    or None for ASCII STL text (starting with ``solid``, no NUL byte in ``head``)."""
    claimed = int(np.frombuffer(head[80:84], "<u4")[0]) if len(head) >= STL_HEADER else None
    if claimed is not None and size == STL_HEADER + STL_RECORD.itemsize * claimed:
        return claimed
    if head.lstrip().lower().startswith(b"solid") and b"\x00" not in head:
        return None
    if claimed is None:
        raise Problem(f"is {size} bytes, too short for a binary STL",
                      "allowed ASCII STL text or a binary STL of 84 + 50 bytes per triangle")
    if claimed == 0:
        raise Problem("has no triangles (its binary STL header counts 0)",
                      "allowed meshes of 1 triangle or more")
    fits = (size - STL_HEADER) / STL_RECORD.itemsize
    shown = f"{fits:,.0f}" if fits == int(fits) else f"{fits:,.2f}"
    raise Problem(f"claims {claimed:,} triangles (binary STL header) but its {size:,} bytes "
                  f"hold {shown}", "allowed 84 + 50 bytes a triangle, or ASCII STL")


def read_binary_stl(data: bytes | memoryview, count: int) -> Geometry:
    """The ``count`` triangles of a binary STL, each with its own three corners (the caller
    welds them)."""
    records = np.frombuffer(data, STL_RECORD, count=count, offset=STL_HEADER)
    corners = records["vertices"].reshape(-1, 3)
    bad = ~np.isfinite(corners)
    if bad.any():
        row, col = np.argwhere(bad)[0]
        raise Problem(f"has the coordinate {_shown_number(float(corners[row, col]))} in "
                      f"triangle {row // 3 + 1:,}", COORD_ALLOWED)
    return Geometry(positions=corners.astype(np.float64),
                    faces=np.arange(3 * count, dtype=np.int64).reshape(-1, 3))


def _keyword(tok: _Tokens, first: np.ndarray, word: bytes) -> np.ndarray:
    """Whether each token starts a statement and is ``word`` (ASCII, any case)."""
    t = tok.text
    hit = first & (tok.ends - tok.starts == len(word))
    for i, c in enumerate(word):
        at = t[np.minimum(tok.starts + i, len(t) - 1)] | 0x20  # ASCII letters in lower case
        hit &= at == c
    return hit


def read_ascii_stl(data: bytes, max_triangles: int | None = None) -> list[Geometry]:
    """The triangles of ASCII STL text, one :class:`Geometry` per ``solid`` (as trimesh read
    them): every ``vertex x y z`` in order, three a facet (the facet normals are ignored)."""
    tok = _Tokens(data)
    first = tok.first
    vertex = _keyword(tok, first, b"vertex")
    _limit(int(vertex.sum()) // 3, max_triangles)
    facet = _keyword(tok, first, b"facet")
    solid = _keyword(tok, first, b"solid")
    keys = np.flatnonzero(vertex)
    head = _heads(first)
    data_tokens = np.flatnonzero(~first & vertex[head])
    ordinal = np.zeros(len(first), np.int64)
    ordinal[keys] = np.arange(len(keys))
    owner = ordinal[head[data_tokens]]
    counts = np.bincount(owner, minlength=len(keys))
    wrong = np.flatnonzero(counts != 3)
    if len(wrong):
        k = keys[wrong[0]]
        raise Problem(f"has a vertex of {_many(counts[wrong[0]], 'number')} at line {tok.line(k)}",
                      "allowed 'vertex x y z' (3 numbers)")
    corners = tok.numbers(data_tokens, np.float64, "a vertex number").reshape(-1, 3)
    _check_range(tok, corners, keys, "coordinate")
    facets = np.flatnonzero(facet)
    if len(facets):
        of = np.searchsorted(facets, keys) - 1  # the facet each vertex is in
        if (of < 0).any():
            k = keys[int(np.argmax(of < 0))]
            raise Problem(f"has a vertex outside a facet at line {tok.line(k)}",
                          "allowed vertices inside 'facet … endfacet'")
        per = np.bincount(of, minlength=len(facets))
        odd = np.flatnonzero(per != 3)
        if len(odd):
            raise Problem(f"has a facet of {_many(per[odd[0]], 'vertex', 'vertices')} at line "
                          f"{tok.line(facets[odd[0]])}", "allowed 3 vertices a facet")
    # the solids: every vertex belongs to the last 'solid' before it
    part = np.searchsorted(np.flatnonzero(solid), keys) - 1
    out = []
    for p in np.unique(part):
        mine = corners[part == p]
        if len(mine) % 3:
            raise Problem(f"has a solid of {len(mine)} vertices, not whole triangles",
                          "allowed 3 vertices a facet")
        out.append(Geometry(positions=mine,
                            faces=np.arange(len(mine), dtype=np.int64).reshape(-1, 3)))
    return out


_GLB_MAGIC = b"glTF"
_CHUNK_JSON = 0x4E4F534A
_CHUNK_BIN = 0x004E4942


def glb_chunks(data: bytes) -> tuple[bytes, bytes | None]:
    """(the JSON chunk, the BIN chunk or None) of a GLB container."""
    if len(data) < 20 or data[:4] != _GLB_MAGIC:
        raise Problem("is not a readable GLB file (it does not start with 'glTF')",
                      "allowed binary glTF 2.0 (.glb)")
    version, length = (int(x) for x in np.frombuffer(data[4:12], "<u4"))
    if version != 2:
        raise Problem(f"is not a readable GLB file (container version {version})",
                      "allowed binary glTF 2.0 (.glb)")
    if not 20 <= length <= len(data):
        raise Problem(f"is not a readable GLB file (its header says {length:,} bytes, the file "
                      f"has {len(data):,})", "allowed a whole .glb file")
    json_length, json_type = (int(x) for x in np.frombuffer(data[12:20], "<u4"))
    if json_type != _CHUNK_JSON or 20 + json_length > length:
        raise Problem("is not a readable GLB file (no JSON chunk after its header)",
                      "allowed binary glTF 2.0 (.glb)")
    text = data[20:20 + json_length]
    at = 20 + json_length + (-json_length % 4)
    binary = None
    if at + 8 <= length:
        chunk_length, chunk_type = (int(x) for x in np.frombuffer(data[at:at + 8], "<u4"))
        if at + 8 + chunk_length > length:
            raise Problem(f"is not a readable GLB file (a chunk of {chunk_length:,} bytes runs "
                          "past its end)", "allowed a whole .glb file")
        if chunk_type == _CHUNK_BIN:
            binary = data[at + 8:at + 8 + chunk_length]
    return text, binary


def glb_container(doc: dict, binary: bytes | None) -> bytes:
    """A GLB file of ``doc`` and a binary chunk."""
    text = json.dumps(doc).encode()
    text += b" " * (-len(text) % 4)
    body = np.array([len(text), _CHUNK_JSON], "<u4").tobytes() + text
    if binary is not None:
        binary = bytes(binary) + b"\x00" * (-len(binary) % 4)
        body += np.array([len(binary), _CHUNK_BIN], "<u4").tobytes() + binary
    return _GLB_MAGIC + np.array([2, 12 + len(body)], "<u4").tobytes() + body


#: what trimesh is not handed of a glTF (Natura shades a user's mesh with its own materials)
_LOOKS_ONLY = ("materials", "images", "textures", "samplers", "cameras", "skins", "animations")


def geometry_only(doc: dict) -> dict:
    """``doc`` as trimesh is handed it: meshes, accessors, buffers and the node tree as they
    are; every material emptied (trimesh reads a primitive's UVs only when it names one), no
    images, textures, cameras, skins or animations (nothing of them is used, and trimesh would
    decode the images)."""
    out = {k: v for k, v in doc.items() if k not in _LOOKS_ONLY}
    if "materials" in doc:
        out["materials"] = [{} for _ in doc["materials"]]
    if "nodes" in doc:
        out["nodes"] = [{k: v for k, v in node.items() if k not in ("camera", "skin")}
                        for node in doc["nodes"]]
    return out


def json_document(text: bytes) -> dict:
    """A glTF's JSON as a dict, refusing what is not JSON, nests deeper than
    :data:`MAX_JSON_DEPTH` or is not an object."""
    try:
        doc = json.loads(text)
    except RecursionError:
        doc = None
        deep = True
    except (ValueError, UnicodeDecodeError) as exc:
        if isinstance(exc, json.JSONDecodeError):
            reason = f"{exc.msg} at line {exc.lineno} column {exc.colno}"
        elif isinstance(exc, UnicodeDecodeError):
            reason = f"not UTF-8 at byte {exc.start:,}"
        else:
            reason = "not JSON"
        raise Problem(f"is not glTF JSON ({reason})", "allowed glTF 2.0 JSON") from None
    else:
        deep = _depth(doc) > MAX_JSON_DEPTH
    if deep:
        raise Problem(f"nests its JSON more than {MAX_JSON_DEPTH} levels deep",
                      f"allowed glTF JSON nested at most {MAX_JSON_DEPTH} levels")
    if not isinstance(doc, dict):
        raise Problem(f"holds {_kind(doc)} where a glTF object belongs",
                      "allowed a glTF 2.0 JSON object")
    return doc


def _depth(doc: Any) -> int:
    """How deep lists and objects nest in ``doc`` (iteratively: no recursion limit)."""
    deepest = 0
    stack = [(doc, 1)]
    while stack:
        item, depth = stack.pop()
        if isinstance(item, dict):
            item = list(item.values())
        if isinstance(item, list):
            deepest = max(deepest, depth)
            if depth > MAX_JSON_DEPTH:
                return depth
            stack.extend((x, depth + 1) for x in item if isinstance(x, (list, dict)))
    return deepest


def _shown(value: Any) -> str:
    """A JSON value as a message shows it: a string quoted, anything cut to 20 characters."""
    return repr(value[:20]) if isinstance(value, str) else json.dumps(value)[:20]


def _kind(value: Any) -> str:
    if isinstance(value, bool):
        return "true/false"
    if isinstance(value, dict):
        return "an object"
    if isinstance(value, list):
        return "a list"
    if isinstance(value, str):
        return "a string"
    if isinstance(value, (int, float)):
        return f"the number {value:g}" if isinstance(value, float) else f"the number {value}"
    return "null"


_COMPONENT_SIZES = {5120: 1, 5121: 1, 5122: 2, 5123: 2, 5125: 4, 5126: 4}
_TYPE_SIZES = {"SCALAR": 1, "VEC2": 2, "VEC3": 3, "VEC4": 4, "MAT2": 4, "MAT3": 9, "MAT4": 16}
_TRIANGLES = (4, 5)  # modes trimesh reads as triangles (GL_TRIANGLES, GL_TRIANGLE_STRIP)
_ARRAYS = ("buffers", "bufferViews", "accessors", "meshes", "nodes", "scenes", "materials",
           "textures", "images", "samplers", "cameras", "skins", "animations")
#: required extensions that change only the look, not the geometry trimesh reads
_LOOKS = ("KHR_materials_", "KHR_texture_", "KHR_lights_", "EXT_texture_")
_SINGULAR = {"buffers": "buffer", "bufferViews": "bufferView", "accessors": "accessor",
             "meshes": "mesh", "nodes": "node", "scenes": "scene", "materials": "material",
             "textures": "texture", "images": "image", "samplers": "sampler",
             "cameras": "camera", "skins": "skin", "animations": "animation"}


class _Gltf:
    """The checks of :func:`check_gltf` over one document."""

    def __init__(self, doc: dict, bin_length: int | None, folder: Path) -> None:
        self.doc = doc
        self.bin_length = bin_length
        self.folder = folder

    def items(self, key: str) -> list[dict]:
        value = self.doc.get(key, [])
        if not isinstance(value, list):
            raise Problem(f"has {key!r} as {_kind(value)}",
                          f"allowed a list of {_SINGULAR[key]} objects")
        for i, item in enumerate(value):
            if not isinstance(item, dict):
                raise Problem(f"has {key}[{i}] as {_kind(item)}",
                              f"allowed {_SINGULAR[key]} objects")
        return value

    def integer(self, owner: str, obj: dict, key: str, low: int, default: int | None = None,
                high: int | None = None) -> int:
        """``obj[key]``: an integer from ``low`` up to ``high`` (exclusive) or beyond."""
        value = obj.get(key, default)
        if value is None:
            raise Problem(f"has {owner} without {key!r}", f"allowed {owner} with {key!r}")
        if not isinstance(value, int) or isinstance(value, bool):
            raise Problem(f"has {owner} {key} as {_kind(value)}", "allowed an integer")
        if value < low or (high is not None and value >= high):
            span = f"{low} to {high - 1:,}" if high is not None else f"{low:,} or more"
            raise Problem(f"has {owner} {key} {value:,}", f"allowed {span}")
        return value

    def index(self, owner: str, obj: dict, key: str, target: str) -> int:
        """``obj[key]``: an index into the document's ``target`` array."""
        count = len(self.doc.get(target, []))
        value = obj.get(key)
        name = _SINGULAR.get(target, target)
        if not isinstance(value, int) or isinstance(value, bool):
            raise Problem(f"has {owner} {key} as {_kind(value)}", f"allowed a {name} index")
        if not 0 <= value < count:
            raise Problem(f"has {owner} pointing at {name} {value:,}, which does not exist",
                          f"allowed {name} 0 to {count - 1:,}" if count else
                          f"allowed none: the file has no {target}")
        return value

    def numbers(self, owner: str, obj: dict, key: str, count: int) -> None:
        value = obj.get(key)
        if value is None:
            return
        if (not isinstance(value, list) or len(value) != count
                or not all(isinstance(x, (int, float)) and not isinstance(x, bool)
                           and math.isfinite(x) for x in value)):
            raise Problem(f"has {owner} {key} that is not {count} finite numbers",
                          f"allowed {count} finite numbers")

    def check(self) -> None:
        doc = self.doc
        asset = doc.get("asset", {})
        version = asset.get("version", "2.0") if isinstance(asset, dict) else None
        if not isinstance(version, str) or not re.fullmatch(r"2(\.\d+)?", version.strip()):
            shown = repr(version) if isinstance(version, str) else _kind(version)
            raise Problem(f"has glTF version {shown[:20]}", "allowed glTF 2.0")
        required = doc.get("extensionsRequired", [])
        if not isinstance(required, list):
            raise Problem(f"has extensionsRequired as {_kind(required)}",
                          "allowed a list of names")
        for name in required:
            if not isinstance(name, str) or not name.startswith(_LOOKS):
                raise Problem(f"requires the glTF extension {str(name)[:40]!r}",
                              "allowed glTF without compressed or extended geometry")
        for key in _ARRAYS:
            self.items(key)
        self.check_buffers()
        self.check_meshes()
        self.check_nodes()

    def check_buffers(self) -> None:
        buffers = self.items("buffers")
        sizes = []
        for i, b in enumerate(buffers):
            declared = self.integer(f"buffer {i}", b, "byteLength", 1)
            actual = self.buffer_size(i, b)
            if actual < declared:
                raise Problem(f"has buffer {i} of {actual:,} bytes, byteLength says "
                              f"{declared:,}", "allowed a byteLength no larger than the data")
            sizes.append(declared)
        views = self.items("bufferViews")
        self.views = []
        for i, v in enumerate(views):
            owner = f"bufferView {i}"
            buffer = self.index(owner, v, "buffer", "buffers")
            start = self.integer(owner, v, "byteOffset", 0, default=0)
            length = self.integer(owner, v, "byteLength", 1)
            if start + length > sizes[buffer]:
                raise Problem(f"has {owner} ending at byte {start + length:,} of buffer "
                              f"{buffer}'s {sizes[buffer]:,}",
                              "allowed bufferViews inside their buffer")
            stride = v.get("byteStride")
            if stride is not None:
                self.integer(owner, v, "byteStride", 4, high=253)
            self.views.append((length, stride))
        accessors = self.items("accessors")
        for i, a in enumerate(accessors):
            owner = f"accessor {i}"
            ctype = a.get("componentType")
            if not (type(ctype) is int and ctype in _COMPONENT_SIZES):
                raise Problem(f"has {owner} componentType {_shown(ctype)}",
                              "allowed 5120, 5121, 5122, 5123, 5125 or 5126")
            kind = a.get("type")
            if not (isinstance(kind, str) and kind in _TYPE_SIZES):
                raise Problem(f"has {owner} type {_shown(kind)}",
                              "allowed SCALAR, VEC2, VEC3, VEC4, MAT2, MAT3 or MAT4")
            count = self.integer(owner, a, "count", 1)
            if "bufferView" not in a:
                continue
            view = self.index(owner, a, "bufferView", "bufferViews")
            offset = self.integer(owner, a, "byteOffset", 0, default=0)
            element = _COMPONENT_SIZES[ctype] * _TYPE_SIZES[kind]
            length, stride = self.views[view]
            end = offset + (count - 1) * (stride or element) + element
            if end > length:
                raise Problem(f"has {owner} needing {end:,} bytes of bufferView {view}'s "
                              f"{length:,}", "allowed accessors inside their bufferView")

    def buffer_size(self, i: int, b: dict) -> int:
        uri = b.get("uri")
        if uri is None:
            if i == 0 and self.bin_length is not None:
                return self.bin_length
            raise Problem(f"has buffer {i} without a uri", "allowed a data: uri, a file next "
                          "to it or (in a .glb) the binary chunk")
        if not isinstance(uri, str):
            raise Problem(f"has buffer {i} uri as {_kind(uri)}", "allowed a string")
        if uri.startswith("data:"):
            head, _, payload = uri.partition(",")
            if not head.endswith(";base64"):
                raise Problem(f"has buffer {i} as a data: uri without base64",
                              "allowed data:...;base64,... buffers")
            try:
                return len(base64.b64decode(payload, validate=True))
            except (binascii.Error, ValueError):
                raise Problem(f"has buffer {i} whose base64 data is broken",
                              "allowed valid base64") from None
        if re.match(r"^[A-Za-z][A-Za-z0-9+.-]*:", uri) and not re.match(r"^[A-Za-z]:[\\/]", uri):
            raise Problem(f"is not a readable GLTF file (buffer {i} is a URL)",
                          "allowed buffers in or next to the file; nothing is downloaded")
        file = self.folder / urllib.parse.unquote(uri)
        try:
            if not file.is_file():
                raise Problem(f"has buffer {i} in {uri[:40]!r}, which is not a file next to it",
                              "allowed buffers in the file or in files next to it")
            return file.stat().st_size
        except OSError:
            raise Problem(f"has buffer {i} in {uri[:40]!r}, which cannot be read",
                          "allowed readable buffer files") from None

    def check_meshes(self) -> None:
        accessors = self.items("accessors")
        for m, mesh in enumerate(self.items("meshes")):
            if "primitives" not in mesh:
                raise Problem(f"has mesh {m} without 'primitives'",
                              "allowed meshes with a list of primitives")
            primitives = mesh["primitives"]
            if not isinstance(primitives, list):
                raise Problem(f"has mesh {m} primitives as {_kind(primitives)}",
                              "allowed a list of primitives")
            for p, prim in enumerate(primitives):
                owner = f"mesh {m} primitive {p}"
                if not isinstance(prim, dict):
                    raise Problem(f"has {owner} as {_kind(prim)}", "allowed an object")
                attributes = prim.get("attributes")
                if not isinstance(attributes, dict):
                    raise Problem(f"has {owner} attributes as {_kind(attributes)}",
                                  "allowed an object of accessor indices")
                for name in attributes:
                    self.index(f"{owner} {name}", attributes, name, "accessors")
                mode = self.integer(owner, prim, "mode", 0, default=4, high=7)
                if "material" in prim:
                    self.index(owner, prim, "material", "materials")
                if "indices" in prim:
                    self.index(f"{owner} indices", prim, "indices", "accessors")
                if mode not in _TRIANGLES:
                    continue
                if "POSITION" not in attributes:
                    raise Problem(f"has {owner} without POSITION",
                                  "allowed triangles with positions")
                self.attribute(owner, "POSITION", accessors, attributes["POSITION"],
                               {"VEC3"}, {5126})
                if "NORMAL" in attributes:
                    self.attribute(owner, "NORMAL", accessors, attributes["NORMAL"], {"VEC3"},
                                   {5126})
                if "TEXCOORD_0" in attributes:
                    self.attribute(owner, "TEXCOORD_0", accessors, attributes["TEXCOORD_0"],
                                   {"VEC2"}, {5126, 5121, 5123})
                corners = accessors[attributes["POSITION"]]["count"]
                if "indices" in prim:
                    self.attribute(owner, "indices", accessors, prim["indices"], {"SCALAR"},
                                   {5121, 5123, 5125})
                    corners = accessors[prim["indices"]]["count"]
                if mode == 4 and corners % 3:
                    raise Problem(f"has {owner} of {corners:,} corners",
                                  "allowed whole triangles (a multiple of 3)")

    def attribute(self, owner: str, name: str, accessors: list, index: int, types: set,
                  components: set) -> None:
        a = accessors[index]
        if a["type"] not in types or a["componentType"] not in components:
            raise Problem(f"has accessor {index} ({name} of {owner}) of {a['type']} "
                          f"{a['componentType']}", f"allowed {'/'.join(sorted(types))} of "
                          + ", ".join(str(c) for c in sorted(components)))
        if "bufferView" not in a or "sparse" in a:
            raise Problem(f"has accessor {index} ({name} of {owner}) compressed or sparse",
                          "allowed plain accessors with a bufferView")

    def check_nodes(self) -> None:
        nodes = self.items("nodes")
        parent: dict[int, int] = {}
        for i, node in enumerate(nodes):
            owner = f"node {i}"
            if "mesh" in node:
                self.index(owner, node, "mesh", "meshes")
            children = node.get("children", [])
            if not isinstance(children, list):
                raise Problem(f"has {owner} children as {_kind(children)}",
                              "allowed a list of node indices")
            for c in children:
                self.index(f"{owner} child", {"child": c}, "child", "nodes")
                if c in parent or c == i:
                    raise Problem(f"has node {c} as a child twice or of itself",
                                  "allowed a tree of nodes (one parent each)")
                parent[c] = i
            for key, count in (("matrix", 16), ("translation", 3), ("rotation", 4), ("scale", 3)):
                self.numbers(owner, node, key, count)
        for start in parent:  # no cycles: walking up from any node ends at a root
            seen = {start}
            up = parent.get(start)
            while up is not None:
                if up in seen:
                    raise Problem(f"has node {start} among its own ancestors",
                                  "allowed a tree of nodes")
                seen.add(up)
                up = parent.get(up)
        for s, scene in enumerate(self.items("scenes")):
            roots = scene.get("nodes", [])
            if not isinstance(roots, list):
                raise Problem(f"has scene {s} nodes as {_kind(roots)}",
                              "allowed a list of node indices")
            for r in roots:
                self.index(f"scene {s}", {"node": r}, "node", "nodes")
        if "scene" in self.doc:
            self.index("its 'scene'", self.doc, "scene", "scenes")


def check_gltf(doc: dict, binary: bytes | None, folder: Path) -> None:
    """A :class:`Problem` for the first thing in a glTF document that does not fit together:
    arrays that are not lists of objects, an index pointing at nothing, a buffer shorter than
    it says, a bufferView or accessor reaching past what holds it, triangles of the wrong
    types or of incomplete triangles, a node tree with loops, a required extension that changes
    the geometry. ``binary`` is a GLB's binary chunk, ``folder`` where buffer files are."""
    _Gltf(doc, None if binary is None else len(binary), folder).check()
