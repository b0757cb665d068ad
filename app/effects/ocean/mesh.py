"""The ocean's level of detail: a polar grid centred under the camera whose rings grow
geometrically (cells about square, one connected mesh: no seams), drawn only in the wedges the
camera sees; displacement fades to flat water toward ``ocean.mesh_extent``, then an analytic
plane reaches the horizon (``glsl/ocean/far.frag``)."""

from __future__ import annotations

import math

import moderngl
import numpy as np

from ...gpu.cache import memoised


def polar_grid(segments: int, inner: float, extent: float):
    """Rest-point mesh around the camera: a centre vertex, then rings r₀ = inner,
    r_{i+1} = r_i·(1 + 2π/segments) up to ``extent`` (cells about square).

    Returns (vertices (V, 3) float32 = (radius, angle, spacing), indices (M,) uint32), triangles
    counter-clockwise seen from above (front faces are the top of the sea), ordered segment by
    segment (all rings of wedge j, then wedge j + 1): a run of wedges is one contiguous range of
    ``len(indices) // segments`` indices each, so the renderer draws only the wedges in view."""
    growth = 1.0 + 2.0 * math.pi / segments
    radii = [0.0, inner]
    while radii[-1] < extent:
        radii.append(min(radii[-1] * growth, extent))
    radii = np.array(radii)
    theta = np.arange(segments) * (2.0 * math.pi / segments)
    spacing = np.maximum(radii * (2.0 * math.pi / segments), inner * 2.0 * math.pi / segments)
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
    return vertices, np.concatenate([fan, quads], axis=1).astype("u4").ravel()


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

    @property
    def built(self) -> bool:
        return self._buffers.built

    def buffers(self, segments: int, inner: float, extent: float):
        """(vertex buffer, index buffer) of the grid."""
        return self._buffers.get((segments, inner, extent))

    def _make(self, key):
        # a pure build of the key, shared by every session of the process (1–2 ms at the
        # tests' 96 segments, 3–9 ms and 3.6 MB at the default 256; sessions draw the same grid)
        verts, idx = memoised(polar_grid, *key)
        self.triangles = len(idx) // 3
        return (self.gpu.buffer(self.owner, "mesh vertices", verts.tobytes()),
                self.gpu.buffer(self.owner, "mesh indices", idx.tobytes()))

    def draw(self, prog, camera, aspect: float, segments: int, inner: float, extent: float,
             cull: bool) -> None:
        """Draw the grid with ``prog`` (attribute ``in_polar``): every wedge, or with ``cull``
        only those :func:`visible_wedges` finds."""
        vbo, ibo = self.buffers(segments, inner, extent)
        vao = prog.vao([(vbo, "3f", "in_polar")], index_buffer=ibo)
        per = 3 * self.triangles // segments  # indices per wedge
        wedges = visible_wedges(camera, aspect, segments) if cull else None
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
