"""Fixtures shared by several tests/gl modules."""

from __future__ import annotations

import pytest

from tests.helpers.planet import PlanetHarness


@pytest.fixture(scope="module")
def planet(gl_ctx):
    """One planet scene per module (tests/gl/test_planet_*.py): programs compile once."""
    h = PlanetHarness(gl_ctx)
    yield h
    h.gpu.release()
