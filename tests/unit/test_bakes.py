"""Cloud noise bakes (issue 3, item 2) without the GPU: the bake specs as parameters (groups,
ranges, defaults, one-line errors) and where the disk cache lives.
"""

from __future__ import annotations

import dataclasses
from pathlib import Path

import pytest

from app.bakes import (
    CACHE_ENV,
    BakeCache,
    DetailBake,
    ShapeBake,
    WeatherBake,
    bake_params,
    default_cache_dir,
)
from app.errors import ParamError
from app.params import ParamSet

# ---- parameters ---------------------------------------------------------------------------------

def test_parameters_are_params_with_groups_ranges_and_defaults():
    params = bake_params()
    groups = {p.group for p in params}
    assert groups == {"bake_shape", "bake_detail", "bake_weather"}
    ps = ParamSet(params)
    for cls in (ShapeBake, DetailBake, WeatherBake):
        default = cls()
        assert cls.from_values(ps.values(cls.group)) == default  # one source for both
        for f in dataclasses.fields(cls):
            p = ps.spec(f"{cls.group}.{f.name}")
            assert p.default == getattr(default, f.name) and p.doc and p.section
    # the GradientSimulator's controls (spec/000 §1.6) are all there
    for name in ("size", "scale", "layers", "persistence", "lacunarity", "offset_x", "offset_y"):
        assert f"bake_weather.{name}" in ps
    assert (ShapeBake().size, DetailBake().size, WeatherBake().size) == (128, 32, 512)
    ps.set_from_string("bake_shape.size=132")
    assert ShapeBake.from_values(ps.values("bake_shape")).size == 132
    with pytest.raises(ParamError, match=r"bake_shape.size=2 is out of range: "
                                         r"allowed an integer in \[8, 256\]"):
        ShapeBake(size=2)
    with pytest.raises(ParamError, match="rising"):
        ShapeBake(cells_g=8, cells_b=8)
    with pytest.raises(ParamError, match="rising"):
        DetailBake(cells_r=4, cells_g=2)
    with pytest.raises(ParamError, match="persistence"):
        WeatherBake(persistence=1.5)
    # whole cells per layer: the map tiles for any lacunarity; offsets wrap into one map
    assert WeatherBake(scale=4, lacunarity=2.5, layers=4).layer_cells()[:5] == [4, 10, 25, 63, 1]
    moved = WeatherBake(offset_x=-1.75, offset_y=3.5)
    assert (moved.offset_x, moved.offset_y) == moved.wrapped_offset() == (0.25, 0.5)
    assert moved == WeatherBake(offset_x=0.25, offset_y=0.5)  # the same image, the same cache key
    with pytest.raises(ParamError, match="offset_x"):
        ps.set("bake_weather.offset_x", 1.5)  # the UI's range is one map


# ---- the cache -----------------------------------------------------------------------------------

def test_cache_directory_from_environment(monkeypatch, tmp_path):
    monkeypatch.setenv(CACHE_ENV, str(tmp_path / "natura-cache"))
    assert default_cache_dir() == tmp_path / "natura-cache"
    assert BakeCache().directory == tmp_path / "natura-cache"
    monkeypatch.delenv(CACHE_ENV)
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path / "xdg"))
    assert default_cache_dir() == tmp_path / "xdg" / "natura" / "bakes"
    monkeypatch.delenv("XDG_CACHE_HOME")
    assert default_cache_dir() == Path.home() / ".cache" / "natura" / "bakes"


# ---- finishing the raw floats -------------------------------------------------------------------

@pytest.mark.parametrize("spec", [ShapeBake(size=16), ShapeBake(size=16, normalize=False),
                                  DetailBake(size=16), WeatherBake(size=32)])
def test_finish_is_quantize_of_normalized_byte_for_byte(spec):
    """finish works a channel at a time in place; the bytes are those of the plain
    definition (normalise over the whole channel, then round(clamp(v, 0, 1) · 255))."""
    import numpy as np

    from app.bakes.core import finish, normalized, quantize

    rng = np.random.default_rng(spec.size)
    raw = (rng.random(spec.array_shape) * 1.6 - 0.3).astype(np.float32)
    raw[..., 0].flat[::7] = np.float32(0.5 / 255.0)  # exactly between two bytes: rint's tie
    raw[..., 1].flat[::11] = np.float32(1.0)
    raw[..., 3] = np.float32(0.25)  # a flat channel (max == min) is left as it is
    want = quantize(normalized(spec, raw))
    got = finish(spec, raw)
    assert got.dtype == np.uint8 and got.shape == raw.shape
    assert np.array_equal(got, want)
