"""Cloud noise bakes: the 3D shape and detail textures and the 2D weather map, baked on the GPU
(compute shaders where GL ≥ 4.3, one fragment pass per slice elsewhere), cached on disk and
checked against numpy twins.

:mod:`.params` holds the specs (one frozen dataclass per kind, its fields the parameters),
:mod:`.core` the bake itself (:func:`bake` → :class:`Baked`), :mod:`.cache` the checked file
format; the numpy twins are ``app/sim/bakes.py`` (:func:`reference`).

Shaders: ``glsl/bakes/cloud_shape.glsl``, ``cloud_detail.glsl``, ``weather_map.glsl`` (headers
with the equations), driven by ``glsl/common/bake3d_compute.glsl`` / ``bake3d_fragment.glsl``.
``tools/bake.py`` fills the cache with the defaults and the maritime sizes and prints times.
"""

from ..sim.bakes import reference
from .cache import BAKE_VERSION, CACHE_ENV, BakeCache, default_cache_dir
from .core import (
    PROGRAMS,
    Baked,
    RawBake,
    bake,
    bake_raw,
    bake_report,
    finish,
    key_for,
    normalized,
    quantize,
    shader_digest,
    shader_files,
)
from .params import DetailBake, ShapeBake, WeatherBake, bake_params, defaults, maritime


def context_path(caps) -> dict[str, str]:
    """The ``context_paths`` entry of an effect that bakes noise: how the bakes run on ``caps``
    (compute shaders where GL ≥ 4.3, else one fragment pass per slice)."""
    how = "compute shaders" if caps.compute else "one fragment pass per slice"
    return {"noise bakes (3D textures)": how}


__all__ = [
    "context_path",
    "bake", "bake_params", "bake_raw", "bake_report",
    "BAKE_VERSION", "BakeCache", "Baked", "CACHE_ENV", "default_cache_dir",
    "defaults", "DetailBake", "finish", "key_for", "maritime", "normalized", "PROGRAMS",
    "quantize", "RawBake", "reference", "shader_digest", "shader_files", "ShapeBake",
    "WeatherBake",
]
