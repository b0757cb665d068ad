"""Cloud noise bakes: the 3D shape and detail textures and the 2D weather map, baked on the GPU
(compute shaders where GL ≥ 4.3, one fragment pass per slice elsewhere), cached on disk and
checked against numpy twins.

* :mod:`.params` — :class:`ShapeBake`, :class:`DetailBake`, :class:`WeatherBake` (frozen
  dataclasses whose fields are the parameters, groups ``bake_shape``, ``bake_detail``,
  ``bake_weather``; :func:`bake_params` lists them as ``app.params.Param``);
* :mod:`.core` — :func:`bake` (and ``bake_shape``/``bake_detail``/``bake_weather``) → :class:`Baked`
  (RGBA8 texels, path, cache status, timings; ``.texture(gpu, owner)`` for renderers), and
  :func:`bake_report` (uncached timings of both paths, for the bench);
* :mod:`.cache` — :class:`BakeCache`, the checked file format, ``$NATURA_CACHE``;
* :func:`reference` — numpy twins of the bake shaders for small sizes (``app/sim/bakes.py``).

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
    bake_detail,
    bake_raw,
    bake_report,
    bake_shape,
    bake_weather,
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
    "bake", "bake_detail", "bake_params", "bake_raw", "bake_report", "bake_shape",
    "BAKE_VERSION", "bake_weather", "BakeCache", "Baked", "CACHE_ENV", "default_cache_dir",
    "defaults", "DetailBake", "finish", "key_for", "maritime", "normalized", "PROGRAMS",
    "quantize", "RawBake", "reference", "shader_digest", "shader_files", "ShapeBake",
    "WeatherBake",
]
