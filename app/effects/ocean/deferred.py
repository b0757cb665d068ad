"""The ocean's deferred surface pass (``ocean.shading = deferred``): the mesh and the far plane
write only their shading inputs into three RGBA32F targets, then one pass shades the pixels they
covered (``glsl/ocean/shade.frag``).

Why: on a software rasteriser (llvmpipe) fragments are shaded in whole 4×4 blocks, and the far
rings of the polar mesh are made of triangles a few pixels wide, so the forward pass shades each
covered pixel several times over; the forward far plane also ran its shading on every pixel of the
screen to keep one band of rows. Here the expensive shading runs once per covered pixel, and the
far plane is drawn only over the rows between the horizon and where the mesh ends
(:func:`far_band`).

* inputs 0 = (p − camera, η), 1 = (rest point − camera.xz, footprint m, kind) with kind 0 = not
  the sea (the clear), 1 = mesh, 2 = far plane; 2 = the rest point's screen derivatives (the
  FFT's mip filter, which the shading pass cannot take from its own neighbours);
* the inputs' framebuffer shares the target's depth, so the mesh and the far plane are depth-tested
  against the scene exactly as the forward passes are (the same fragments win);
* the shading quad lies on the far plane and is tested GREATER against that depth: pixels nothing
  drew over are rejected before the shader runs.
"""

from __future__ import annotations

import math

import moderngl
import numpy as np


def far_band(camera, aspect: float, rows: int, far_start: float,
             margin: int = 2) -> tuple[float, float] | None:
    """NDC heights (bottom, top) of the band of screen rows where the far plane can show: rows
    whose rays meet y = 0 (below the horizon) at a horizontal distance ≥ ``far_start`` for at
    least one pixel — or None when no row does (camera at or below y = 0, looking up or steeply
    down). The camera has no roll (``app.sim.camera.Camera``: its right vector is horizontal), so
    a row's rays share dir.y and the widest horizontal reach of a row is at its edge columns,
    |dir.xz|² = |f.xz + y·tanθ·u.xz|² + (tanθ·aspect)²; a ray meets the plane beyond R when
    −dir.y · R ≤ y_cam · |dir.xz|. ``margin`` rows are added on each side (float32 in the
    shader against float64 here)."""
    height = float(camera.position[1])
    if height <= 0.0 or rows <= 0:
        return None
    _, u, f = camera.basis()
    th = math.tan(math.radians(camera.fov) * 0.5)
    ys = (np.arange(rows) + 0.5) / rows * 2.0 - 1.0
    d = f[None, :] + ys[:, None] * th * u[None, :]
    reach = np.sqrt(d[:, 0] ** 2 + d[:, 2] ** 2 + (th * aspect) ** 2)
    down = -d[:, 1]
    hits = np.nonzero((down > 0.0) & (down * far_start <= height * reach * (1.0 + 1e-3)))[0]
    if hits.size == 0:
        return None
    lo = max(int(hits.min()) - margin, 0)
    hi = min(int(hits.max()) + 1 + margin, rows)
    return lo / rows * 2.0 - 1.0, hi / rows * 2.0 - 1.0


def deferred_inputs(gpu, owner: str, size: tuple[int, int], depth) -> tuple:
    """The three RGBA32F input targets of the deferred pass (position, surface, gradients) for a
    render target of ``size``, a framebuffer over them that shares the target's ``depth``, and
    one over the surface target alone, to clear its kind without touching the depth:
    ``(rel, surf, grad, fbo, clear_fbo)``."""
    nearest = (moderngl.NEAREST, moderngl.NEAREST)
    rel, surf, grad = (gpu.texture(owner, f"deferred inputs ({what})", size, 4, dtype="f4",
                                   filter=nearest) for what in ("position", "surface", "gradients"))
    fbo = gpu.framebuffer(owner, "deferred inputs", [rel, surf, grad], depth_attachment=depth)
    return rel, surf, grad, fbo, gpu.framebuffer(owner, "deferred inputs (clear)", [surf])


def screen_rect(view_proj_rel: np.ndarray, bounds: tuple[float, float, float, float],
                heights: tuple[float, float], size: tuple[int, int]) -> tuple[int, int, int, int]:
    """The pixels (x, y, width, height) a camera-relative box covers on a ``size`` screen: the
    box ``bounds`` = (x min, z min, x max, z max) [m, relative to the camera] between the heights
    ``heights`` [m, relative to the camera], clipped against the near side (w > 0: the parts of
    the box behind the camera are cut off, not projected through it), then projected; (0, 0, 0,
    0) when nothing of it is in front of the camera or on screen."""
    x0, z0, x1, z1 = bounds
    if not (x1 >= x0 and z1 >= z0):
        return (0, 0, 0, 0)
    corners = np.array([(x, y, z, 1.0) for x in (x0, x1) for y in heights for z in (z0, z1)])
    clip = corners @ np.asarray(view_proj_rel, dtype=float).T
    eps = 1e-6
    points = [c for c in clip if c[3] > eps]
    for i in range(8):
        for j in range(i + 1, 8):
            if bin(i ^ j).count("1") != 1:  # the 12 edges join corners differing in one axis
                continue
            a, b = clip[i], clip[j]
            if (a[3] > eps) != (b[3] > eps):
                f = (eps - a[3]) / (b[3] - a[3])
                points.append(a + f * (b - a))
    if not points:
        return (0, 0, 0, 0)
    pts = np.array(points)
    ndc = pts[:, :2] / pts[:, 3:4]
    lo = np.clip(np.min(ndc, axis=0), -1.0, 1.0)
    hi = np.clip(np.max(ndc, axis=0), -1.0, 1.0)
    w, h = size
    px0, py0 = int(math.floor((lo[0] + 1.0) * 0.5 * w)), int(math.floor((lo[1] + 1.0) * 0.5 * h))
    px1, py1 = int(math.ceil((hi[0] + 1.0) * 0.5 * w)), int(math.ceil((hi[1] + 1.0) * 0.5 * h))
    if px1 <= px0 or py1 <= py0:
        return (0, 0, 0, 0)
    return (px0, py0, px1 - px0, py1 - py0)


def wake_map(gpu, owner: str, size: tuple[int, int], stride: int) -> tuple:
    """The deferred pass's wake foam per block of ``stride`` × ``stride`` pixels
    (``glsl/ocean/wake_map.frag``): an R32F texture of the screen's ``size`` over the stride,
    and its framebuffer."""
    texture = gpu.texture(owner, "wake map", (-(-size[0] // stride), -(-size[1] // stride)), 1,
                          dtype="f4")
    return texture, gpu.framebuffer(owner, "wake map", [texture])
