"""Temporal reprojection of the cloud layer: the Bayer order that picks one pixel of each 4×4
block per frame.
"""

from __future__ import annotations

from app.effects.clouds.reprojection import BAYER4, block_pixel


def test_bayer_order_visits_every_pixel_of_a_block():
    assert sorted(BAYER4) == list(range(16))
    assert {block_pixel(i) for i in range(16)} == {(x, y) for x in range(4) for y in range(4)}
