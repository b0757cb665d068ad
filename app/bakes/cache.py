"""The on-disk bake cache: baked textures as checked files, never trusted blindly.

Where: ``$NATURA_CACHE`` if set (the directory itself), else ``~/.cache/natura/bakes``
(``$XDG_CACHE_HOME/natura/bakes`` where that is set). An explicit directory beats both.

Key: SHA-256 of a canonical JSON of the bake kind, every parameter (size included), the bake
format version :data:`BAKE_VERSION` (bumped when the Python side of a bake changes: the
normalisation, the quantisation), a digest of every GLSL file both bake programs include
(editing a shader invalidates its bakes) and, for Perlin bakes, the permutation table of the
seed. The file is named ``<kind>-<size>-<first 16 hex digits of the key>.bake``.

File format (little-endian)::

    offset 0   8 bytes   magic b"NATBAKE\\n"
           8   u32       FILE_FORMAT (1)
          12   u32       header length H
          16   H bytes   header, UTF-8 JSON: key, kind, shape, dtype ("uint8" or "float32"),
                         payload_bytes, path, bake_seconds, renderer, created, params
        16+H   N bytes   payload: the texels, C order, shape as in the header, little-endian
         end   32 bytes  SHA-256 of everything before it

Reading checks, in order: length, magic ("foreign"), format ("foreign"), header length and
payload length ("truncated"), checksum ("corrupt"), header JSON ("corrupt"), key ("stale"),
kind/shape/dtype ("stale"). Any failure — or any OSError — is a miss with a reason; the bake
is redone and the file rewritten. Writes go to a temporary file in the same directory, are
flushed and fsynced, then ``os.replace``-d over the old file (atomic on POSIX and Windows), so
a crash mid-write leaves the old file or none, never half a file. A directory that cannot be
created or written turns caching off for that call with one warning per directory.
"""

from __future__ import annotations

import contextlib
import hashlib
import json
import os
import struct
import time
import warnings
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from ..errors import NaturaWarning, quote_path
from ..sim.textures import write_atomic

CACHE_ENV = "NATURA_CACHE"
MAGIC = b"NATBAKE\n"
FILE_FORMAT = 1
#: Bump when the Python side of any bake changes what ends up in the file.
BAKE_VERSION = 1
_PREFIX = struct.Struct("<8sII")
_DIGEST = 32
_MAX_HEADER = 1 << 20
_warned: set[str] = set()


def default_cache_dir() -> Path:
    """``$NATURA_CACHE``, else ``$XDG_CACHE_HOME/natura/bakes``, else ``~/.cache/natura/bakes``."""
    env = os.environ.get(CACHE_ENV)
    if env:
        return Path(env).expanduser()
    xdg = os.environ.get("XDG_CACHE_HOME")
    base = Path(xdg).expanduser() if xdg else Path.home() / ".cache"
    return base / "natura" / "bakes"


def _warn_once(directory: Path, why: str) -> None:
    tag = str(directory)
    if tag not in _warned:
        _warned.add(tag)
        warnings.warn(f"bake cache {quote_path(tag)} {why}: baking without the cache (allowed "
                      f"${CACHE_ENV} or ~/.cache naming a folder you can write)", NaturaWarning,
                      stacklevel=3)


def _folder_problem(folder: Path, exc: OSError) -> str:
    """Why a cache folder could not be made, in words: a file in its way is named as such."""
    for part in (folder, *folder.parents):
        if part.exists() and not part.is_dir():
            return ("is a file, not a folder" if part == folder
                    else f"cannot be made: {quote_path(part)} is a file")
    return f"cannot be created ({exc.strerror or exc})"


def cache_key(kind: str, params: dict[str, Any], shader_digest: str,
              extra: dict[str, Any] | None = None) -> str:
    """SHA-256 hex of everything a bake's bytes depend on (see the module doc)."""
    doc = {"kind": kind, "params": params, "bake_version": BAKE_VERSION, "file_format": FILE_FORMAT,
           "glsl": shader_digest, "extra": extra or {}}
    text = json.dumps(doc, sort_keys=True, separators=(",", ":"), default=str)
    return hashlib.sha256(text.encode("utf-8")).hexdigest()


def driver(ctx) -> list:
    """What a GPU bake's texels depend on beside their inputs: the context's driver."""
    return [ctx.info.get(k) for k in ("GL_VENDOR", "GL_RENDERER", "GL_VERSION")]


@dataclass
class CacheRead:
    """What a lookup found: ``data`` (None on a miss), ``status`` "hit" | "miss" | "rebuilt"
    (a file was there but unusable) and ``reason``; ``header`` of a hit."""

    data: np.ndarray | None
    status: str
    reason: str = ""
    header: dict | None = None


class BakeCache:
    """Bake files in one directory (see the module doc). ``directory=None`` picks
    :func:`default_cache_dir` at construction time."""

    def __init__(self, directory: str | os.PathLike | None = None):
        self.directory = (Path(directory).expanduser() if directory is not None
                          else default_cache_dir())

    def path_for(self, kind: str, size: int, key: str) -> Path:
        return self.directory / f"{kind}-{int(size)}-{key[:16]}.bake"

    def load(self, path: Path, key: str, kind: str, shape: tuple[int, ...],
             dtype: str = "uint8") -> CacheRead:
        """The array in ``path`` if the file is whole, ours, current and of the expected shape
        and dtype (``uint8`` texels, or ``float32`` ones: the planet's ground noise)."""
        try:
            blob = Path(path).read_bytes()
        except FileNotFoundError:
            return CacheRead(None, "miss")
        except OSError as exc:
            return CacheRead(None, "rebuilt", f"unreadable ({exc.strerror or exc})")
        try:
            return self._parse(blob, key, kind, tuple(int(s) for s in shape), np.dtype(dtype))
        except Exception as exc:  # never trust, never crash: anything odd is a rebuild
            return CacheRead(None, "rebuilt", f"corrupt ({type(exc).__name__}: {exc})")

    @staticmethod
    def _parse(blob: bytes, key: str, kind: str, shape: tuple[int, ...],
               dtype: np.dtype) -> CacheRead:
        def bad(reason: str) -> CacheRead:
            return CacheRead(None, "rebuilt", reason)

        if len(blob) < _PREFIX.size + _DIGEST:
            if blob[: len(MAGIC)] != MAGIC[: len(blob)]:
                return bad("foreign (not a Natura bake file)")
            return bad(f"truncated ({len(blob)} bytes)")
        magic, fmt, header_len = _PREFIX.unpack_from(blob)
        if magic != MAGIC:
            return bad("foreign (not a Natura bake file)")
        if fmt != FILE_FORMAT:
            return bad(f"foreign (file format {fmt}, this version reads {FILE_FORMAT})")
        if header_len > _MAX_HEADER or _PREFIX.size + header_len + _DIGEST > len(blob):
            return bad(f"truncated (header of {header_len} bytes in a {len(blob)}-byte file)")
        view = memoryview(blob)  # slices of it are not copies (a shape bake is 8 MiB)
        body, digest = view[:-_DIGEST], blob[-_DIGEST:]
        header_bytes = body[_PREFIX.size:_PREFIX.size + header_len]
        try:
            header = json.loads(bytes(header_bytes).decode("utf-8"))
            payload_bytes = int(header["payload_bytes"])
        except (UnicodeDecodeError, ValueError, KeyError, TypeError):
            header, payload_bytes = None, -1
        payload = body[_PREFIX.size + header_len:]
        if header is not None and len(payload) < payload_bytes:
            return bad(f"truncated ({len(payload)} of {payload_bytes} payload bytes)")
        if hashlib.sha256(body).digest() != digest:
            return bad("corrupt (checksum mismatch)")
        if header is None or len(payload) != payload_bytes:
            return bad("corrupt (header)")
        if header.get("key") != key:
            return bad("stale (made with other parameters or shaders)")
        if (header.get("kind") != kind or tuple(header.get("shape", ())) != shape
                or header.get("dtype") != dtype.name):
            return bad(f"stale (holds {header.get('kind')} {header.get('shape')} "
                       f"{header.get('dtype')})")
        if payload_bytes != int(np.prod(shape)) * dtype.itemsize:
            return bad("corrupt (payload size does not match the shape)")
        data = np.frombuffer(payload, dtype=dtype.newbyteorder("<")).reshape(shape).astype(dtype)
        return CacheRead(data, "hit", "", header)

    def store(self, path: Path, key: str, kind: str, data: np.ndarray,
              meta: dict[str, Any] | None = None) -> bool:
        """Write ``data`` (uint8 or float32, stored little-endian) atomically. False, with one
        warning per directory, when the directory cannot be created or written."""
        if np.dtype(data.dtype).name not in ("uint8", "float32"):
            raise TypeError(f"bake cache stores uint8 or float32 texels, got {data.dtype}")
        data = np.ascontiguousarray(data, dtype=np.dtype(data.dtype).newbyteorder("<"))
        header = {"key": key, "kind": kind, "shape": list(data.shape),
                  "dtype": np.dtype(data.dtype).name,
                  "payload_bytes": int(data.nbytes),
                  "created": time.strftime("%Y-%m-%dT%H:%M:%S%z"),
                  **(meta or {})}
        header_bytes = json.dumps(header, sort_keys=True, default=str).encode("utf-8")
        body = _PREFIX.pack(MAGIC, FILE_FORMAT, len(header_bytes)) + header_bytes + data.tobytes()
        blob = body + hashlib.sha256(body).digest()
        path = Path(path)
        try:
            path.parent.mkdir(parents=True, exist_ok=True)
        except OSError as exc:
            _warn_once(path.parent, _folder_problem(path.parent, exc))
            return False
        try:
            write_atomic(path, blob)
            return True
        except OSError as exc:
            _warn_once(path.parent, f"cannot be written ({exc.strerror or exc})")
            return False

    def keep_newest(self, kind: str, count: int) -> None:
        """Remove all but the ``count`` newest files of ``kind`` (a size dragged in the panel
        writes one file a size); another process then misses, never fails."""
        try:
            found = [(f.stat().st_mtime_ns, f) for f in self.directory.glob(f"{kind}-*.bake")]
        except OSError:
            return
        for _, old in sorted(found, reverse=True)[count:]:
            with contextlib.suppress(OSError):
                old.unlink()

    def files(self) -> list[Path]:
        try:
            return sorted(self.directory.glob("*.bake"))
        except OSError:
            return []
