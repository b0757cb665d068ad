"""The ocean's level of detail: a polar grid centred under the camera whose rings grow
geometrically (cells about square, one connected mesh: no seams), drawn only in the wedges the
camera sees; displacement fades to flat water toward ``ocean.mesh_extent``, then an analytic
plane reaches the horizon (``glsl/ocean/far.frag``)."""

from __future__ import annotations

import math

import moderngl
import numpy as np

from ...gpu.cache import memoised

#: wedges drawn or culled together: inside a group the triangles run ring chunk by ring chunk
GROUP = 8
#: triangles of one wedge in a chunk (the fan, then two per ring)
CHUNK = 64


def polar_grid(segments: int, inner: float, extent: float, aspect: float = 0.0,
               height: float = 1.0):
    """Rest-point mesh around the camera: a centre vertex, then rings r₀ = inner,
    r(i+1) = r(i)·(1 + s(i)·2π/segments) up to ``extent``, where s(i) = 1 (cells about square)
    out to ``aspect``·``height`` and s(i) = r(i)/(``aspect``·``height``) beyond it (``aspect`` ≤ 0:
    square cells everywhere).

    Why the stretch: seen from a height h, a ring at distance r ≫ h shrinks on screen by h/r
    across the view (its depression angle is about h/r) while a wedge keeps its angular width
    2π/segments, so square cells far away turn into slivers a fraction of a pixel tall — most
    of the mesh's triangles, each costing a software rasteriser its setup. Growing the rings by
    r/(aspect·h) keeps every far cell's on-screen height at 1/``aspect`` of its width; beyond
    aspect·h the grid then has only about segments/2π more rings, whatever its extent. The
    vertex spacing (column 2) stays the arc, the side the view does not foreshorten: read at the
    coarser mip level of the stretched side, the far waves flatten, and the image strays further
    from a fine mesh's (measured in tests/gl/test_maritime.py).

    Returns (vertices (V, 3) float32 = (radius, angle, spacing), indices (M,) uint32), triangles
    counter-clockwise seen from above (front faces are the top of the sea), ordered group by
    group of :data:`GROUP` wedges: a run of whole groups is one contiguous range of
    ``len(indices) // segments`` indices a wedge, so the renderer draws only the groups in view.
    Inside a group the triangles run chunk by chunk outward (:data:`CHUNK` of each wedge, wedge
    after wedge), so neighbouring wedges' shared vertices are near each other in the index
    stream: a software renderer's vertex stage (llvmpipe's, on one thread) reuses a vertex it
    shaded only within a short run of indices, and wedge after wedge it shaded each column of
    vertices twice."""
    step = 2.0 * math.pi / segments
    knee = aspect * height if aspect > 0.0 else math.inf  # where the cells start to stretch
    radii = [0.0, inner]
    while radii[-1] < extent:
        r = radii[-1]
        radii.append(min(r * (1.0 + step * max(1.0, r / knee)), extent))
    radii = np.array(radii)
    theta = np.arange(segments) * step
    spacing = np.maximum(radii * step, inner * step)  # the arc: the mip level (see above)
    # vertices column by column (all rings at angle θ_j), so a run of wedges also reads one
    # contiguous range of vertices: software rasterisers shade every vertex in the index range
    nr = len(radii) - 1
    verts = np.empty((1 + segments * nr, 3))
    verts[0] = (0.0, 0.0, spacing[1])
    columns = verts[1:].reshape(segments, nr, 3)
    columns[:, :, 0] = radii[1:]
    columns[:, :, 1] = theta[:, None]
    columns[:, :, 2] = spacing[1:]
    vertices = verts.astype("f4")
    # wedge j: the fan triangle at the centre, then two triangles per ring i (whole arrays,
    # not a loop over the wedges: the same integers)
    j = np.arange(segments)[:, None]
    first = 1 + j * nr  # ring 0 at θ_j
    after = 1 + (j + 1) % segments * nr  # ring 0 at θ_{j+1}
    rings = np.arange(nr - 1)[None, :]
    a, b = first + rings, after + rings  # ring i at θ_j, at θ_{j+1}
    quads = np.stack([a, b, b + 1, a, b + 1, a + 1], axis=-1).reshape(segments, -1, 3)
    fan = np.stack([np.zeros_like(first), after, first], axis=-1)
    # (θ grows from +x toward +z, so θ_j → θ_{j+1} → outward is counter-clockwise seen from +y)
    wedges = np.concatenate([fan, quads], axis=1)  # (segments, triangles a wedge, 3)
    per = wedges.shape[1]
    order = [wedges[g:g + GROUP, c:c + CHUNK].reshape(-1, 3)
             for g in range(0, segments, GROUP) for c in range(0, per, CHUNK)]
    return vertices, np.concatenate(order).astype("u4").ravel()


def stretch_height(current: float, camera_height: float) -> float:
    """The height the far rings are stretched for (:func:`polar_grid`): a power of two near the
    camera's height above the mean water level (at least 0.5 m), kept (``current``) while the
    camera stays within [⅔, 3]× of it, so a bobbing camera does not rebuild the grid. A camera
    higher than the grid's height sees its far cells up to 3× taller than ``aspect`` asks, a
    lower one flatter; ``current`` ≤ 0: none chosen yet."""
    h = max(abs(float(camera_height)), 0.5)
    if current > 0.0 and current / 1.5 <= h <= 3.0 * current:
        return float(current)
    return float(2.0 ** math.floor(math.log2(h)))


def visible_wedges(camera, aspect: float, segments: int, margin: int = 2):
    """Index ranges (first wedge, count) of the polar grid's wedges the camera can see, or None
    for all of them. The grid's angle θ runs from +x toward +z; a wedge is visible when its
    azimuth lies within the frustum's horizontal spread (from its corner rays) plus a margin —
    unless a corner ray points down or up steeply enough to see past the camera's feet."""
    r, u, f = camera.basis()
    th = math.tan(math.radians(camera.fov) * 0.5)
    corners = [f + sx * th * aspect * r + sy * th * u for sx in (-1, 1) for sy in (-1, 1)]
    fh = np.array([f[0], 0.0, f[2]])
    if np.linalg.norm(fh) < 1e-6:
        return None
    fh /= np.linalg.norm(fh)
    rh = np.array([-fh[2], 0.0, fh[0]])
    spread = 0.0
    for d in corners:
        ahead = float(d @ fh)
        if ahead <= 1e-3:
            return None
        spread = max(spread, abs(math.atan2(float(d @ rh), ahead)))
    step = 2.0 * math.pi / segments
    centre = math.atan2(fh[2], fh[0]) % (2.0 * math.pi)
    half = int(math.ceil(spread / step)) + margin
    if 2 * half + 1 >= segments:
        return None
    first = int(math.floor(centre / step)) - half
    return first % segments, 2 * half + 2


def whole_groups(first: int, count: int, segments: int):
    """The run of whole groups of :data:`GROUP` wedges (first, count) that covers the wedges
    ``first`` … ``first + count − 1`` (mod ``segments``), or None when that is every wedge."""
    start = first - first % GROUP
    end = first + count
    if end <= segments:
        end = min(-(-end // GROUP) * GROUP, segments)
    else:  # the run wraps past the last wedge: its tail in whole groups from wedge 0
        end = segments + -(-(end - segments) // GROUP) * GROUP
    return None if end - start >= segments else (start, end - start)


class OceanMesh:
    """The polar grid's GPU buffers (remade when its shape changes) and the draw of the wedges
    in view."""

    def __init__(self, effect):
        self.gpu = effect.gpu
        self.owner = effect.name
        self._buffers = effect.keyed(self._make,
                                     release=lambda objs: [self.gpu.free(o) for o in objs])
        self.triangles = 0  # in the whole mesh
        self.drawn = 0  # in the last draw
        self.height = 0.0  # the camera height the far rings were stretched for (0: none yet)

    @property
    def built(self) -> bool:
        return self._buffers.built

    def _make(self, key):
        # a pure build of the key, shared by every session of the process (1–2 ms at the
        # tests' 96 segments, 3–9 ms and 3.6 MB at the default 256; sessions draw the same grid)
        verts, idx = memoised(polar_grid, *key)
        self.triangles = len(idx) // 3
        return (self.gpu.buffer(self.owner, "mesh vertices", verts.tobytes()),
                self.gpu.buffer(self.owner, "mesh indices", idx.tobytes()))

    def draw(self, prog, camera, aspect: float, segments: int, inner: float, extent: float,
             cull: bool, cell_aspect: float = 0.0) -> None:
        """Draw the grid with ``prog`` (attribute ``in_polar``): every wedge, or with ``cull``
        the whole groups of those :func:`visible_wedges` finds; far cells stretched to
        ``cell_aspect`` (0: none) for the camera's height (:func:`stretch_height`, kept
        between frames)."""
        height = 1.0
        if cell_aspect > 0.0:
            height = self.height = stretch_height(self.height, camera.position[1])
        vbo, ibo = self._buffers.get((segments, inner, extent, float(cell_aspect), height))
        vao = prog.vao([(vbo, "3f", "in_polar")], index_buffer=ibo)
        per = 3 * self.triangles // segments  # indices per wedge
        wedges = visible_wedges(camera, aspect, segments) if cull else None
        if wedges is not None:
            wedges = whole_groups(*wedges, segments)
        if wedges is None:
            vao.render(moderngl.TRIANGLES)
            self.drawn = self.triangles
        else:
            first, count = wedges
            head = min(count, segments - first)
            vao.render(moderngl.TRIANGLES, vertices=head * per, first=first * per)
            if count > head:
                vao.render(moderngl.TRIANGLES, vertices=(count - head) * per, first=0)
            self.drawn = count * per // 3
