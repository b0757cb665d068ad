"""What a live session holds, for the tests that change parameters frame after frame as the
window's panel does (tests/stability/test_live_changes.py): the GL objects of its context and
the process's resident memory."""

from __future__ import annotations

import ctypes
import gc
import os
from collections import Counter

import moderngl

#: every kind of GL object moderngl makes (not ``Scope``: a saved state holds no GL name, and a
#: program's uniforms and attributes are not objects)
GL_TYPES = (moderngl.Buffer, moderngl.Texture, moderngl.Texture3D, moderngl.TextureArray,
            moderngl.TextureCube, moderngl.Framebuffer, moderngl.Renderbuffer,
            moderngl.VertexArray, moderngl.Program, moderngl.ComputeShader, moderngl.Sampler,
            moderngl.Query)
#: the names of their native halves (what moderngl queues on ``ctx.objects``)
GL_NAMES = frozenset(t.__name__ for t in GL_TYPES)


def _gl_classes() -> set[type]:
    """The classes of :data:`GL_TYPES` and their subclasses."""
    out: set[type] = set()
    todo = list(GL_TYPES)
    while todo:
        cls = todo.pop()
        out.add(cls)
        todo.extend(cls.__subclasses__())
    return out


def watch(ctx: moderngl.Context) -> None:
    """Have moderngl queue the GL name of every object of ``ctx`` that Python drops without a
    release (``gc_mode = "context_gc"``: ``ctx.objects``; without it such an object leaks and
    no count can see it). The queued ones are not released: :func:`gl_objects` counts them."""
    ctx.gc_mode = "context_gc"


def gl_objects(ctx: moderngl.Context) -> Counter:
    """The GL objects of ``ctx`` that exist now, by kind: every moderngl object of the context
    not released (found among Python's objects: a cache, a list or a dict that keeps one keeps it
    counted), and — with :func:`watch` — those dropped without a release ("dropped"). Entries of
    objects dropped after their release, and of scopes (``ctx.scope``: no GL name, nothing to
    release), are removed from ``ctx.objects`` here: nothing of them is left to count, and the
    queue would grow."""
    gc.collect()
    counts: Counter = Counter()
    # the exact type against a set, not isinstance against twelve classes: the walk covers
    # every object of the worker's process (millions after a few hundred tests)
    kinds = _gl_classes()
    for obj in [o for o in gc.get_objects() if type(o) in kinds]:
        if (getattr(obj, "ctx", None) is ctx
                and not isinstance(obj.mglo, moderngl.InvalidObject)):
            counts[type(obj).__name__] += 1
    queued = getattr(ctx, "objects", None)
    if queued is not None:
        alive = [m for m in queued if type(m).__name__ in GL_NAMES]
        queued.clear()
        queued.extend(alive)
        if alive:
            counts["dropped"] = len(alive)
    return counts


def rss_mb() -> float:
    """The process's resident memory [MiB], after handing freed heap back to the system (glibc's
    ``malloc_trim``: otherwise freed arrays linger in the arenas as fragments and RSS moves by
    tens of MB with no leak at all)."""
    try:
        ctypes.CDLL(None).malloc_trim(0)
    except (OSError, AttributeError):  # not glibc: nothing to trim
        pass
    with open("/proc/self/statm") as f:
        return int(f.read().split()[1]) * os.sysconf("SC_PAGE_SIZE") / 2**20
