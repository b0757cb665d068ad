"""Tessellation of the sphere and torus from their projected size (materials.tessellation = auto)
against the fixed 48 × 96 segments: fewer triangles where the objects are small, with the image
within a stated bound of the fixed meshes', and no under-tessellation where they are large."""

from __future__ import annotations

import numpy as np
import pytest

from app.colour import linear_to_srgb
from app.effects.materials.effect import MATERIAL, MATERIAL_OBJECT_POS
from app.runtime import open_session, scene_params

#: the stated bound at 320×180 (measured 0.56 % and 0.0022 at edges of 6 px)
CHANGED_SHARE_MAX = 0.015  # pixels whose display value moves by > 0.05
MEAN_ABS_MAX = 0.005


@pytest.fixture
def session(gl_ctx):
    s = open_session("materials", scene_params("materials"), ctx=gl_ctx)
    yield s
    s.release()


def shoot(session, size, tessellation, spec=MATERIAL, edge_pixels=None):
    p = session.params
    p.set("materials.tessellation", tessellation)
    if edge_pixels is not None:
        p.set("materials.edge_pixels", edge_pixels)
    eff = session.scene.effect("materials")
    target = session.gpu.target("test", "tessellation", size)
    try:
        frame = session.scene.frame(size)
        target.use()
        target.clear((0, 0, 0, 0))
        eff.draw(frame, target, spec)
        return target.read().astype(np.float64), eff.triangles(), dict(eff.last_meshes)
    finally:
        session.gpu.free(target)


def test_auto_is_coarser_when_small_and_close_to_fixed(session):
    size = (320, 180)
    fixed, tri_fixed, _ = shoot(session, size, "fixed")
    auto, tri_auto, meshes = shoot(session, size, "auto")
    assert tri_auto < 0.25 * tri_fixed, (tri_auto, tri_fixed)
    d = np.abs(linear_to_srgb(auto[..., :3]) - linear_to_srgb(fixed[..., :3])).max(axis=-1)
    assert (d > 0.05).mean() <= CHANGED_SHARE_MAX, (d > 0.05).mean()
    assert d.mean() <= MEAN_ABS_MAX, d.mean()
    # the level is kept while the view stays in it: the same mesh objects on the next frame
    _, _, again = shoot(session, size, "auto")
    assert all(again[n] is meshes[n] for n in meshes)


def _coverage(img):
    return img[..., 3] > 0.5


def _boundary(mask):
    edge = np.zeros_like(mask)
    edge[:-1] |= mask[:-1] != mask[1:]
    edge[:, :-1] |= mask[:, :-1] != mask[:, 1:]
    return int(edge.sum())


def test_auto_does_not_under_tessellate_when_large(session):
    size = (1280, 720)
    # the reference: edges of 1 px, the finest level (192 segments) for both objects
    fine, tri_fine, _ = shoot(session, size, "auto", MATERIAL_OBJECT_POS, edge_pixels=1.0)
    auto, tri_auto, _ = shoot(session, size, "auto", MATERIAL_OBJECT_POS, edge_pixels=6.0)
    fixed, _, _ = shoot(session, size, "fixed", MATERIAL_OBJECT_POS)
    ref = _coverage(fine)
    silhouette = _boundary(ref)
    off_auto = int((_coverage(auto) != ref).sum())
    off_fixed = int((_coverage(fixed) != ref).sum())
    assert tri_fine > tri_auto
    # silhouette error: pixels covered differently from the fine mesh, per outline pixel — a
    # mean displacement of the outline in pixels. At most 0.1 px (measured 0.047: the torus's
    # tube at 24 segments, sagitta ≈ 0.26 px at its 32 px radius; the fixed meshes 0.022)
    assert off_auto <= 0.1 * silhouette, (off_auto, off_fixed, silhouette)
    assert off_fixed <= off_auto  # the finer fixed mesh is the closer one: the test can tell
