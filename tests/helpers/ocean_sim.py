"""Numpy oceans the tests build and the app does not."""

from __future__ import annotations

from typing import Sequence

import numpy as np

from app.sim.ocean import Cascade, FFTOcean, SpectrumParams


def ocean_from_cascades(params: SpectrumParams, cascades: Sequence[Cascade],
                        choppiness: float = 1.0) -> FFTOcean:
    """The ocean of these cascades as they are (each on its own grid, e.g. cropped to what
    a view resolves: :func:`app.sim.ocean.crop_cascade`), of the sea ``params``."""
    held = tuple((c.patch_size, c.band, c.kx, c.kz, c.omega, c.h0) for c in cascades)
    ocean = FFTOcean(params, n=int(np.shape(cascades[0].h0)[-1]),
                     patch_sizes=[c.patch_size for c in cascades], choppiness=choppiness,
                     build=lambda *_: held)
    ocean.n = max(int(np.shape(c.h0)[-1]) for c in cascades)
    return ocean
