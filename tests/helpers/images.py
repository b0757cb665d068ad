"""Reading back the images Natura writes (PNG as 8-bit RGB, EXR as float32 RGB) and the GPU
targets the tests inspect."""

from __future__ import annotations

import os

import numpy as np


def read_png(path: str | os.PathLike) -> np.ndarray:
    from PIL import Image

    with Image.open(path) as im:
        return np.asarray(im.convert("RGB"))


def read_exr(path: str | os.PathLike) -> np.ndarray:
    import OpenEXR

    with OpenEXR.File(str(path)) as f:
        channels = f.channels()
        if "RGB" in channels:
            return np.asarray(channels["RGB"].pixels, dtype=np.float32)
        return np.stack([np.asarray(channels[c].pixels, dtype=np.float32) for c in "RGB"], axis=-1)


def read_aux(layer) -> np.ndarray:
    """An app.render.amortise.LayerHistory's aux target: (h, w, 4) float32, row 0 at the top:
    cloud distance, clipped scene distance, marched fraction (1: the pixel's own march; 0:
    filled from its neighbours), 0."""
    w, h = layer.size
    data = np.frombuffer(layer.aux.read(), dtype=np.float32).reshape(h, w, 4)
    return data[::-1].copy()


def read_face(point, f: int) -> np.ndarray:
    """Face f of an app.render.shadow_maps point-light map: the stored (|l| + bias)/range,
    (face, face), row 0 at v = 0."""
    w, h = point.colour.size
    c = np.frombuffer(point.colour.read(), np.float32).reshape(h, w, 2)[..., 0]
    face = c.shape[0] // 2
    return c[(f // 3) * face:(f // 3 + 1) * face, (f % 3) * face:(f % 3 + 1) * face]
