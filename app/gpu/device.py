"""The GPU as the app sees it: a context, its capabilities, the shader library, and a record of
every resource each effect allocated (so tests can check that a scene creates nothing it does
not use, and the panel can list what a scene holds)."""

from __future__ import annotations

import contextlib
import ctypes
import gc
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Iterator

import moderngl
import numpy as np

from .context import Caps, caps_of, create_headless_context
from .programs import ProgramSpec
from .rawgl import CubeFaceCopy
from .shaders import Program, ShaderLibrary
from .targets import RenderTarget


@dataclass
class Allocation:
    owner: str  # effect or scene name
    kind: str  # program | texture | cubemap | target | buffer
    name: str
    obj: Any


class Gpu:
    def __init__(self, ctx: moderngl.Context | None = None, shader_root: Path | None = None):
        #: a context made here is ours to release; a window's context belongs to the window
        self.owns_context = ctx is None
        self.ctx = ctx or create_headless_context()
        self.caps: Caps = caps_of(self.ctx)
        # Seamless cubemap filtering (core since GL 3.2, off by default): without it the blurred
        # mip levels of the sky's environment cubemap show the face edges as lines in reflections.
        self.ctx.enable_direct(0x884F)  # GL_TEXTURE_CUBE_MAP_SEAMLESS
        self.shaders = ShaderLibrary(self.ctx, shader_root)
        self.allocations: list[Allocation] = []
        #: progress(label, fraction) for long GPU jobs such as bakes; the window draws a bar
        self.progress = None
        self._cube_face_copy: Any = None

    @contextlib.contextmanager
    def keep_framebuffer(self) -> Iterator[None]:
        """Work that binds framebuffers of its own while a caller's is bound — a producer that
        renders on request, in the middle of its consumer's pass (the sky's cubemap by fragment
        passes, a bake) — gives the caller back its framebuffer and viewport: otherwise the
        consumer's next draw lands in the producer's target (on a context without compute
        shaders, where such work runs as fragment passes, the ocean's deferred shading did)."""
        before: moderngl.Framebuffer | None = self.ctx.fbo
        if before is not None and isinstance(before.mglo, moderngl.InvalidObject):
            before = None  # released since it was bound: nothing to give back
        viewport = self.ctx.viewport
        try:
            yield
        finally:
            if before is not None and not isinstance(before.mglo, moderngl.InvalidObject):
                before.use()
                self.ctx.viewport = viewport

    def copy_to_cube_face(self, cube: moderngl.TextureCube, face: int, level: int,
                          size: int) -> None:
        """The bound framebuffer's lower-left ``size``² into ``cube``'s ``face`` at mip
        ``level``, on the GPU (``app.gpu.rawgl.CubeFaceCopy``)."""
        if self._cube_face_copy is None:
            self._cube_face_copy = CubeFaceCopy(self.ctx)
        self._cube_face_copy(cube, face, level, size)

    def _record(self, owner: str, kind: str, name: str, obj: Any) -> Any:
        self.allocations.append(Allocation(owner, kind, name, obj))
        return obj

    def program(self, owner: str, spec: ProgramSpec | str, defines: dict | None = None,
                **stages) -> Program:
        """The compiled program of ``spec`` (a :class:`ProgramSpec`, or a library name with
        ``defines`` and explicit stage files), recorded under ``owner``."""
        if isinstance(spec, ProgramSpec):
            name, defines, stages = (spec.name, {**dict(spec.defines), **(defines or {})},
                                     spec.stages())
        else:
            name = spec
        prog = self.shaders.program(name, defines, **stages)
        if not any(a.obj is prog and a.owner == owner for a in self.allocations):
            self._record(owner, "program", name, prog)
        return prog

    def texture(self, owner: str, name: str, size, components: int, data=None, dtype: str = "f4",
                filter=(moderngl.LINEAR, moderngl.LINEAR),
                repeat: bool = False, samples: int = 0) -> moderngl.Texture:
        """A 2D texture; ``samples`` > 0 makes it multisampled (no data, filter or repeat:
        a multisampled texture is only rendered to, resolved or texelFetch-ed)."""
        if samples:
            tex = self.ctx.texture(tuple(size), components, dtype=dtype, samples=samples)
            return self._record(owner, "texture", name, tex)
        tex = self.ctx.texture(tuple(size), components, data=data, dtype=dtype)
        tex.filter = filter
        tex.repeat_x = tex.repeat_y = repeat
        return self._record(owner, "texture", name, tex)

    def array_texture(self, owner: str, name: str, data, repeat: bool = True) -> moderngl.Texture:
        """A 2D texture of an (h, w, c) array: 8-bit normalised from uint8, else float32."""
        data = np.ascontiguousarray(data)
        h, w = data.shape[:2]
        return self.texture(owner, name, (w, h), data.shape[2], data=data.tobytes(),
                            dtype="f1" if data.dtype == np.uint8 else "f4", repeat=repeat)

    def texture_cube(self, owner: str, name: str, size: int, components: int = 4,
                     dtype: str = "f2"):
        cube = self.ctx.texture_cube((size, size), components, dtype=dtype)
        return self._record(owner, "cubemap", name, cube)

    def buffer(self, owner: str, name: str, data: bytes):
        return self._record(owner, "buffer", name, self.ctx.buffer(data))

    def texture3d(self, owner: str, name: str, size, components: int, data=None, dtype: str = "f4",
                  filter=(moderngl.LINEAR, moderngl.LINEAR), repeat: bool = True):
        tex = self.ctx.texture3d(tuple(size), components, data=data, dtype=dtype)
        tex.filter = filter
        tex.repeat_x = tex.repeat_y = tex.repeat_z = repeat
        return self._record(owner, "texture3d", name, tex)

    def depth_texture(self, owner: str, name: str, size, samples: int = 0):
        if samples:
            return self._record(owner, "texture", name,
                                self.ctx.depth_texture(tuple(size), samples=samples))
        tex = self.ctx.depth_texture(tuple(size))
        tex.repeat_x = tex.repeat_y = False
        return self._record(owner, "texture", name, tex)

    def framebuffer(self, owner: str, name: str, color_attachments, depth_attachment=None):
        return self._record(owner, "framebuffer", name,
                            self.ctx.framebuffer(color_attachments=list(color_attachments),
                                                 depth_attachment=depth_attachment))

    def target(self, owner: str, name: str, size, dtype: str = "f4",
               depth: bool = True, samples: int = 0) -> RenderTarget:
        """A float render target (``samples`` > 0: multisampled, to be resolved)."""
        return self._record(owner, "target", name,
                            RenderTarget(self.ctx, size, dtype=dtype, depth=depth,
                                         samples=samples))

    @contextlib.contextmanager
    def scratch_target(self, owner: str, name: str, size, **kw) -> Iterator[RenderTarget]:
        """:meth:`target` for a ``with`` block, freed after it."""
        target = self.target(owner, name, size, **kw)
        try:
            yield target
        finally:
            self.free(target)

    def owned_by(self, owner: str) -> list[Allocation]:
        return [a for a in self.allocations if a.owner == owner]

    def free(self, obj: Any) -> None:
        """Release one resource and forget it (a buffer: with the vertex arrays the programs
        cached for it, see ``Program.forget_buffer``)."""
        for a in list(self.allocations):
            if a.obj is obj:
                self.allocations.remove(a)
        if isinstance(obj, (RenderTarget, moderngl.Framebuffer)):
            self._park()
        if isinstance(obj, moderngl.Buffer):
            for prog in self.shaders.programs():
                prog.forget_buffer(obj)
        if not isinstance(obj, Program):  # programs are shared through the library
            obj.release()

    def _park(self) -> None:
        """Bind a 1×1 framebuffer of our own before a framebuffer is deleted: deleting the bound
        one leaves GL (and moderngl's record of the binding) pointing at a dead object, and the
        next framebuffer creation fails with GL_INVALID_OPERATION."""
        extra = self.ctx.extra if isinstance(self.ctx.extra, dict) else {}
        self.ctx.extra = extra
        if "natura.parking" not in extra:  # one per context, kept as long as the context
            extra["natura.parking"] = self.ctx.framebuffer([self.ctx.texture((1, 1), 4)])
        extra["natura.parking"].use()

    def release_owner(self, owner: str) -> None:
        for a in self.owned_by(owner):
            self.free(a.obj)

    def release(self) -> None:
        """Free everything this Gpu allocated, and the context itself when it made it (a
        script that opens many sessions must not keep one EGL context, ~8–35 MB, per session).
        Safe to call twice."""
        for a in list(self.allocations):
            self.free(a.obj)
        self.shaders.release()
        extra = self.ctx.extra if isinstance(self.ctx.extra, dict) else {}
        parking = extra.pop("natura.parking", None)
        if parking is not None:
            for tex in parking.color_attachments:
                tex.release()
            parking.release()
        if self.owns_context:
            self.owns_context = False
            self.ctx.release()
            _return_freed_memory()


#: a full garbage collection at every this many releases of a context made here (see
#: :func:`_return_freed_memory`)
RELEASES_PER_COLLECT = 4
_releases = 0


def _return_freed_memory() -> None:
    """Hand the driver's freed heap back to the system: llvmpipe's per-context allocations
    otherwise stay in glibc's arenas as fragments, and RSS creeps up by a few MB per released
    session although nothing leaks. A released session's reference cycles (~130 small objects)
    are collected at every :data:`RELEASES_PER_COLLECT`-th release, not at each: a full
    collection walks the whole heap (40–47 ms in a test process) to find a few tens of kB."""
    global _releases
    _releases += 1
    if _releases % RELEASES_PER_COLLECT == 0:
        gc.collect()
    with contextlib.suppress(OSError, AttributeError):  # not glibc (musl, macOS): no trim
        ctypes.CDLL(None).malloc_trim(0)
