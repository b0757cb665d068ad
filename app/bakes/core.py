"""Baking the cloud noise textures on the GPU, through the disk cache.

``bake(gpu, spec)`` → :class:`Baked`: looks the spec up in the cache (:mod:`app.bakes.cache`);
on a miss it runs the bake shader (``glsl/bakes/<name>.comp`` where GL ≥ 4.3, else one
full-screen pass per slice with ``<name>.frag`` — ``app.gpu.bake.bake_volume``), reads the
RGBA32F result back, normalises the Worley channels (``normalize``) and quantises to RGBA8
(:func:`finish`), writes the cache file and returns the bytes with timings. ``Baked.texture``
makes the GL texture a renderer samples (RGBA8, repeat, trilinear with mipmaps — the cloud
thesis lowers the level of detail along light rays, spec/001 §1.1).

Quantisation: u8 = round(clamp(v, 0, 1) · 255) on the CPU, so the stored bytes do not depend
on how a driver converts floats to unorm. Normalisation (on by default for the Worley
channels): v' = (v − min) / (max − min) over the whole baked channel — an affine map, so
tiling and frequency content are kept, and each Worley channel spans [0, 1] (spec/001 §6
criterion B1).
"""

from __future__ import annotations

import hashlib
import time
from dataclasses import dataclass
from pathlib import Path
from typing import Callable

import moderngl
import numpy as np

from ..errors import GpuUnavailableError
from ..gpu.bake import bake_volume, read_volume
from ..gpu.device import Gpu
from ..gpu.programs import ProgramSpec
from ..gpu.shaders import ShaderLibrary, SourceError, read_source
from ..render.noise import GradientNoiseTextures
from ..sim.noise import gradient
from .cache import BakeCache, cache_key
from .params import defaults, maritime

OWNER = "bakes"


@dataclass(frozen=True)
class BakePrograms:
    """The two programs of a bake kind: compute (GL ≥ 4.3) and per-slice fragment."""

    compute: ProgramSpec
    fragment: ProgramSpec
    perlin: bool  # binds a Perlin permutation texture

    @classmethod
    def named(cls, name: str, perlin: bool) -> "BakePrograms":
        return cls(ProgramSpec(f"bakes/{name}", comp=f"bakes/{name}.comp", requires_compute=True),
                   ProgramSpec(f"bakes/{name}", vert="common/fullscreen.vert",
                               frag=f"bakes/{name}.frag"),
                   perlin)


PROGRAMS: dict[str, BakePrograms] = {
    "shape": BakePrograms.named("cloud_shape", perlin=True),
    "detail": BakePrograms.named("cloud_detail", perlin=False),
    "weather": BakePrograms.named("weather_map", perlin=True),
}


def shader_files(library: ShaderLibrary, kind: str) -> list[Path]:
    """Every GLSL file the compute and fragment programs of ``kind`` include."""
    progs = PROGRAMS[kind]
    files: list[Path] = []
    for spec in (progs.compute, progs.fragment):
        for path in library.stage_files(spec.name, **spec.stages()).values():
            files.extend(library.preprocess(path, dict(spec.defines)).files)
    return list(dict.fromkeys(files))


def shader_digest(library: ShaderLibrary, kind: str) -> str:
    """SHA-256 over the names (relative to the shader root) and bytes of :func:`shader_files`."""
    h = hashlib.sha256()
    for path in sorted(shader_files(library, kind), key=lambda p: p.as_posix()):
        try:
            name = path.resolve().relative_to(library.root).as_posix()
        except ValueError:
            name = path.as_posix()
        h.update(name.encode("utf-8") + b"\0")
        try:  # the library's reader: never blocks on a pipe, refuses folders and huge files
            text = read_source(path)
        except SourceError as exc:  # the bake's compile names the error; the key just differs
            text = f"<unreadable: {exc}>"
        h.update(text.encode("utf-8") + b"\0")
    return h.hexdigest()


def key_for(spec, library: ShaderLibrary) -> str:
    """The cache key of ``spec`` (parameters, kind, versions, shaders, Perlin table)."""
    extra = {}
    if PROGRAMS[spec.kind].perlin:
        table = gradient.permutation(spec.seed).astype("<i8").tobytes()
        extra["perlin_permutation"] = hashlib.sha256(table).hexdigest()
    return cache_key(spec.kind, spec.values(), shader_digest(library, spec.kind), extra)


@dataclass
class RawBake:
    """The float channels as the GPU wrote them (before :func:`finish`)."""

    data: np.ndarray  # float32, spec.array_shape
    seconds: float  # GPU bake time (``finish()`` around the passes; the compile is done before)
    path: str  # "compute" | "fragment"


def bake_raw(gpu, spec, use_compute: bool | None = None,
             progress: Callable[[float], None] | None = None,
             chunk_slices: int | None = None, owner: str = OWNER) -> RawBake:
    """Run the bake shader and read the RGBA32F result back (no cache, no quantisation)."""
    progs = PROGRAMS[spec.kind]
    if use_compute is None:
        use_compute = gpu.caps.compute
    if use_compute and not gpu.caps.compute:
        raise GpuUnavailableError("a compute bake needs GL 4.3; this context has "
                                  f"{gpu.caps.describe()}: allowed use_compute=False or None "
                                  "(the fragment path)")
    chosen = progs.compute if use_compute else progs.fragment
    gpu.program(owner, chosen)  # compile outside the timing
    perms = GradientNoiseTextures(gpu, owner) if progs.perlin else None
    uniforms = spec.uniforms()

    def setup(prog):
        if perms is not None:
            prog.bind_textures(perms.textures(spec.seed))
        prog.set_many(uniforms)

    result = None
    try:
        result = bake_volume(gpu, owner, f"{spec.kind} bake {spec.size}", spec.volume_size,
                             progs.compute, progs.fragment, setup, use_compute=use_compute,
                             progress=progress, chunk_slices=chunk_slices)
        data = read_volume(result.texture)
    finally:
        if result is not None:
            gpu.free(result.texture)
        if perms is not None:
            perms.release()
    data = data.reshape(spec.array_shape)
    return RawBake(np.ascontiguousarray(data), result.seconds, result.path)


def normalized(spec, raw: np.ndarray) -> np.ndarray:
    """``raw`` (float) with the spec's Worley channels stretched to [0, 1] when ``normalize``
    is on (float64)."""
    out = np.array(raw, dtype=np.float64)
    if getattr(spec, "normalize", False):
        for c in spec.worley_channels:
            lo, hi = float(out[..., c].min()), float(out[..., c].max())
            if hi > lo:
                out[..., c] = (out[..., c] - lo) / (hi - lo)
    return out


def quantize(values: np.ndarray) -> np.ndarray:
    """round(clamp(v, 0, 1) · 255) as uint8."""
    return np.rint(np.clip(values, 0.0, 1.0) * 255.0).astype(np.uint8)


def finish(spec, raw: np.ndarray) -> np.ndarray:
    """Raw float channels → the stored RGBA8 texels (normalise, then quantise):
    ``quantize(normalized(spec, raw))`` byte for byte, one channel at a time in place (the
    same float64 operations in the same order; a 128³ shape bake in ~30 ms instead of
    ~200–350 ms of whole-volume float64 temporaries)."""
    out = np.empty(raw.shape, dtype=np.uint8)
    stretched = set(spec.worley_channels) if getattr(spec, "normalize", False) else set()
    for c in range(raw.shape[-1]):
        v = raw[..., c].astype(np.float64)
        if c in stretched:
            lo, hi = float(v.min()), float(v.max())
            if hi > lo:
                v -= lo
                v /= hi - lo
        np.clip(v, 0.0, 1.0, out=v)
        v *= 255.0
        np.rint(v, out=v)
        out[..., c] = v
    return out


@dataclass
class Baked:
    """A bake as the app uses it: the RGBA8 texels and how they were obtained.

    ``data``: uint8, (depth, height, width, 4) or (height, width, 4), texel (0, 0[, 0]) first
    (GL order: row 0 is v = 0). ``cache``: "hit", "miss" (no file), "rebuilt" (a file was
    there but unusable: ``cache_reason`` says why) or "off" (no cache, or it could not be
    written). ``path``: "compute" or "fragment" — how the texels were baked (for a hit: by the
    run that wrote the file). ``bake_seconds``: GPU time of the bake in this call, without the
    shader compile (0 on a hit);
    ``seconds``: wall time of the whole call (lookup, bake, readback, write).
    """

    spec: object
    data: np.ndarray
    key: str
    path: str
    cache: str
    cache_reason: str = ""
    cache_file: Path | None = None
    bake_seconds: float = 0.0
    seconds: float = 0.0
    recorded_bake_seconds: float = 0.0  # the bake time stored with a cached file
    renderer: str = ""

    @property
    def kind(self) -> str:
        return self.spec.kind

    @property
    def hit(self) -> bool:
        return self.cache == "hit"

    @property
    def nbytes(self) -> int:
        return int(self.data.nbytes)

    def summary(self) -> str:
        size = "×".join(str(s) for s in self.data.shape[:-1][::-1])
        how = (f"cache hit (baked by {self.path} in {self.recorded_bake_seconds:.2f} s)"
               if self.hit else
               f"{self.path} {self.bake_seconds:.2f} s, cache {self.cache}"
               + (f": {self.cache_reason}" if self.cache_reason else ""))
        return (f"{self.kind} {size} RGBA8 {self.nbytes / 2**20:.1f} MiB: {how}; "
                f"call {self.seconds:.2f} s")

    def texture(self, gpu, owner: str, mipmaps: bool = True, name: str | None = None):
        """The GL texture (RGBA8, repeat on every axis, linear filtering; trilinear with
        mipmaps), allocated under ``owner``: Texture3D for shape/detail, Texture for weather."""
        name = name or f"{self.kind} noise {self.spec.size}"
        data = np.ascontiguousarray(self.data).tobytes()
        if self.data.ndim == 4:
            d, h, w, _ = self.data.shape
            tex = gpu.texture3d(owner, name, (w, h, d), 4, data=data, dtype="f1", repeat=True)
        else:
            h, w, _ = self.data.shape
            tex = gpu.texture(owner, name, (w, h), 4, data=data, dtype="f1", repeat=True)
        if mipmaps:
            tex.build_mipmaps()
            tex.filter = (moderngl.LINEAR_MIPMAP_LINEAR, moderngl.LINEAR)
        else:
            tex.filter = (moderngl.LINEAR, moderngl.LINEAR)
        return tex


def _cache_arg(cache) -> BakeCache | None:
    if cache is False:
        return None
    if cache is None or cache is True:
        return BakeCache()
    if isinstance(cache, BakeCache):
        return cache
    return BakeCache(cache)  # a directory


def bake(gpu, spec, *, cache=None, use_compute: bool | None = None,
         progress: Callable[[float], None] | None = None, chunk_slices: int | None = None,
         owner: str = OWNER) -> Baked:
    """The RGBA8 texels of ``spec`` (a ShapeBake, DetailBake or WeatherBake), from the cache
    when a valid file is there, else baked on the GPU and written to the cache.

    ``cache``: None/True = :class:`BakeCache` at the default directory, a path or a BakeCache,
    or False (no cache). ``use_compute``: None = compute where GL ≥ 4.3. ``progress(f)``, f in
    (0, 1], is called after each slice (fragment) or chunk (compute), and with 1.0 at the end
    (a hit reports 1.0 at once). ``chunk_slices``: z slices per compute dispatch."""
    t0 = time.perf_counter()
    store = _cache_arg(cache)
    key = key_for(spec, gpu.shaders)
    reason, status, file = "", "off", None
    if store is not None:
        file = store.path_for(spec.kind, spec.size, key)
        found = store.load(file, key, spec.kind, spec.array_shape)
        if found.data is not None:
            header = found.header or {}
            if progress:
                progress(1.0)
            return Baked(spec, found.data, key, str(header.get("path", "?")), "hit", "", file, 0.0,
                         time.perf_counter() - t0, float(header.get("bake_seconds", 0.0)),
                         str(header.get("renderer", "")))
        status, reason = found.status, found.reason

    scaled = None if progress is None else (lambda f: progress(0.95 * f))
    raw = bake_raw(gpu, spec, use_compute, scaled, chunk_slices, owner)
    data = finish(spec, raw.data)
    renderer = gpu.caps.describe()
    if store is not None:
        meta = {"path": raw.path, "bake_seconds": raw.seconds, "renderer": renderer,
                "params": spec.values()}
        if not store.store(file, key, spec.kind, data, meta):
            status, reason, file = "off", "cache directory not writable", None
    if progress:
        progress(1.0)
    return Baked(spec, data, key, raw.path, status, reason, file, raw.seconds,
                 time.perf_counter() - t0, raw.seconds, renderer)


def bake_report(gpu=None, specs=None, paths=("compute", "fragment"), repeat: int = 1) -> list[dict]:
    """Bake each spec (default: the cloud thesis's defaults and the maritime sizes) with each
    path, uncached, and return one row per (spec, path): kind, size, path, seconds (median of
    ``repeat``), texels, MiB (RGBA8), texels per second, renderer. A path the context lacks
    (compute below GL 4.3) is skipped. Programs are compiled by a tiny warm-up bake first, so
    the times are the bakes alone."""
    own = gpu is None
    if own:
        gpu = Gpu()
    rows = []
    try:
        for spec in specs or (defaults() + maritime()):
            for path in paths:
                if path == "compute" and not gpu.caps.compute:
                    continue
                bake_raw(gpu, spec.replace(size=8), use_compute=(path == "compute"))  # compile
                times = [bake_raw(gpu, spec, use_compute=(path == "compute")).seconds
                         for _ in range(max(1, repeat))]
                seconds = float(np.median(times))
                texels = int(np.prod(spec.volume_size))
                rows.append({"kind": spec.kind, "size": spec.size, "path": path, "seconds": seconds,
                             "texels": texels, "mib": spec.nbytes / 2**20,
                             "texels_per_s": texels / seconds,
                             "renderer": gpu.caps.describe()})
    finally:
        if own:
            gpu.release()
            gpu.ctx.release()
    return rows
