"""What a bake is made of: one frozen dataclass per bake kind, whose fields are the bake's
parameters (``app.params.Param`` metadata on each field, so the same table feeds the UI,
``--set``, presets, validation and the cache key).

Parameter groups (``<group>.<field>``):

* ``bake_shape`` — :class:`ShapeBake`, the 3D RGBA cloud shape noise (spec/001 §1.1, texture
  table "Shape"; spec/000 §1.6 "Volume noise");
* ``bake_detail`` — :class:`DetailBake`, the 3D detail noise, RGB + A = 1 (spec/001 §1.1
  "Detail"; spec/000 §1.6 "Detail noise", spec/000 §6 criterion 15);
* ``bake_weather`` — :class:`WeatherBake`, the 2D weather / coverage map (spec/001 §1.1
  "Weather map"; spec/000 §1.6 GradientSimulator: scale, layers, persistence, lacunarity,
  offset).

Neither thesis gives cell counts, octave counts or seeds; the defaults here are ours and are
chosen so the frequency order the theses ask for holds (spec/001 §6 criterion B3: shape
R < G < B < A, detail R < G < B; spec/000 §6 criterion 14) — tests/**/test_bakes*.py check
it. Sizes: the cloud
thesis's 128³ / 32³ / 512² are the defaults; :func:`maritime` gives the maritime thesis's
132³ / 64³ ("17.5 MB" and "2 MB" there, which the spec infers were RGBA half floats; 8.8 MiB
and 1 MiB here in RGBA8; "~11 ms" each on the thesis's GPU).
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass, field
from typing import Any, ClassVar, Mapping

from ..errors import ParamError
from ..params import Joint, Param

SPEC_SHAPE = "spec/001 §1.1 (texture table, Shape); spec/000 §1.6 (NoiseSimulator)"
SPEC_DETAIL = "spec/001 §1.1 (texture table, Detail); spec/000 §1.6 (NoiseSimulator)"
SPEC_WEATHER = "spec/000 §1.6 (GradientSimulator); spec/001 §1.1 (texture table, Weather map)"

#: Seeds stay below 2^24 so the per-channel Worley seeds seed·8 + channel never wrap uint32.
MAX_SEED = 2**24 - 1


def _p(default, lo=None, hi=None, doc="", kind="float", unit="", section="", step=None):
    """A dataclass field carrying the keyword arguments of its Param."""
    return field(default=default, metadata={"param": dict(lo=lo, hi=hi, doc=doc, kind=kind,
                                                           unit=unit, section=section,
                                                           step=step)})


_PARAMS: dict[tuple[type, str], Param] = {}  # _BakeSpec.param's, per (class, field)


class _BakeSpec:
    """Shared behaviour of the bake dataclasses (``kind``, ``group``, parameters, checks)."""

    kind: ClassVar[str] = ""
    group: ClassVar[str] = ""
    dims: ClassVar[int] = 3
    #: channels stretched to [0, 1] by their min and max when ``normalize`` is on
    worley_channels: ClassVar[tuple[int, ...]] = ()

    def __post_init__(self):
        for f in dataclasses.fields(self):
            object.__setattr__(self, f.name, self.param(f.name).validate(getattr(self, f.name)))
        self.check()

    #: rules between fields (``app.params.Joint`` over ``<group>.<field>`` names), shown beside
    #: their ranges and checked by :meth:`check`
    joints: ClassVar[tuple[Joint, ...]] = ()

    def check(self) -> None:
        """Constraints between fields (raise ParamError)."""
        values = {f"{self.group}.{f.name}": getattr(self, f.name)
                  for f in dataclasses.fields(self)}
        for j in self.joints:
            if j.broken_by(values) is not None:
                shown = ", ".join(f"{n}={values[n]}" for n in j.names)
                raise ParamError(f"{shown}: allowed {j.text}")

    @classmethod
    def param(cls, name: str) -> Param:
        # made once per class and field: a spec is built every frame a texture is asked for,
        # and each build validates every field (making the Params each time cost the clouds
        # about 3 ms a frame on a 2-core machine)
        key = (cls, name)
        made = _PARAMS.get(key)
        if made is None:
            f = {f.name: f for f in dataclasses.fields(cls)}[name]
            meta = dict(f.metadata["param"])
            full = f"{cls.group}.{name}"
            made = _PARAMS[key] = Param(full, f.default, **meta,
                                        joint=tuple(j for j in cls.joints if full in j.names))
        return made

    @classmethod
    def params(cls) -> list[Param]:
        """Every field as an ``app.params.Param`` named ``<group>.<field>``."""
        return [dataclasses.replace(cls.param(f.name)) for f in dataclasses.fields(cls)]

    @classmethod
    def from_values(cls, values: Mapping[str, Any]):
        """From a mapping of ``<group>.<field>`` or bare field names (others are ignored), e.g.
        ``ShapeBake.from_values(param_set.values("bake_shape"))``."""
        names = {f.name for f in dataclasses.fields(cls)}
        kw = {}
        for key, value in values.items():
            group, _, short = key.rpartition(".")
            if short in names and group in ("", cls.group):
                kw[short] = value
        return cls(**kw)

    def values(self) -> dict[str, Any]:
        """``{"<group>.<field>": value}`` — what a ParamSet holds."""
        return {f"{self.group}.{k}": v for k, v in dataclasses.asdict(self).items()}

    def replace(self, **changes):
        return dataclasses.replace(self, **changes)

    @property
    def volume_size(self) -> tuple[int, int, int]:
        """(width, height, depth) of the bake as a volume (a 2D map is one slice deep)."""
        n = int(self.size)
        return (n, n, n) if self.dims == 3 else (n, n, 1)

    @property
    def array_shape(self) -> tuple[int, ...]:
        """Shape of the baked array: (depth, height, width, 4) or (height, width, 4)."""
        n = int(self.size)
        return (n, n, n, 4) if self.dims == 3 else (n, n, 4)

    @property
    def nbytes(self) -> int:
        """Bytes of the RGBA8 texture."""
        return math.prod(self.array_shape)

    def uniforms(self) -> dict[str, Any]:
        """The bake shader's uniforms (each kind defines its own)."""
        raise TypeError(f"{type(self).__name__} is abstract: use ShapeBake, DetailBake or "
                        "WeatherBake")


@dataclass(frozen=True)
class ShapeBake(_BakeSpec):
    """3D RGBA cloud shape noise: R = Perlin–Worley, G/B/A = inverted-Worley fBm with rising
    cell counts (glsl/bakes/cloud_shape.glsl has the equations)."""

    kind: ClassVar[str] = "shape"
    group: ClassVar[str] = "bake_shape"
    worley_channels: ClassVar[tuple[int, ...]] = (1, 2, 3)

    size: int = _p(128, 8, 256, "texels per side (128 cloud thesis; 132 maritime thesis; staged as "
                   "RGBA32F: 16 B per texel on the GPU)", "int",
                   "texels", SPEC_SHAPE)
    seed: int = _p(0, 0, MAX_SEED, "noise seed (0: Perlin's own permutation; Worley seeds seed·8 + "
                   "channel)", "int", "", SPEC_SHAPE)
    base_cells: int = _p(3, 1, 64, "R: Perlin lattice cells and Worley cells per tile (few: the "
                         "base shape)", "int", "cells", SPEC_SHAPE)
    perlin_octaves: int = _p(5, 1, 16, "R: octaves of the Perlin fBm", "int", "",
                             "spec/001 §1.1; spec/001 eq. 3.2")
    base_worley_octaves: int = _p(3, 1, 16, "R: octaves of the Worley fBm that billows the Perlin "
                                  "fBm", "int", "", "spec/001 §1.1; spec/001 eq. 3.2")
    cells_g: int = _p(4, 1, 128, "G: Worley cells per tile (octave 0)", "int", "cells", SPEC_SHAPE)
    cells_b: int = _p(8, 1, 128, "B: Worley cells per tile (octave 0)", "int", "cells", SPEC_SHAPE)
    cells_a: int = _p(16, 1, 128, "A: Worley cells per tile (octave 0)", "int", "cells", SPEC_SHAPE)
    worley_octaves: int = _p(3, 1, 16, "G/B/A: octaves of each Worley fBm", "int", "",
                             "spec/001 §1.1; spec/001 eq. 3.2")
    gain: float = _p(0.5, 0.0, 1.0, "octave gain G = 2^-H of every sum (\"usually 1/2\")", "float",
                     "", "spec/001 §1.1; spec/001 eq. 3.2")
    normalize: bool = _p(True, doc="stretch G/B/A to [0, 1] by their min and max (spec/001 §6 "
                         "criterion B1)", kind="bool", section="spec/001 §6 (criterion B1)")

    joints: ClassVar[tuple[Joint, ...]] = (Joint(
        ("bake_shape.cells_g", "bake_shape.cells_b", "bake_shape.cells_a"),
        "bake_shape.cells_g < cells_b < cells_a (rising cell counts, G to A)",
        lambda g, b, a: g < b < a),)

    def uniforms(self) -> dict[str, Any]:
        return {"uShapeSeed": self.seed, "uShapeBasePeriod": self.base_cells,
                "uShapePerlinOctaves": self.perlin_octaves,
                "uShapeBaseWorleyOctaves": self.base_worley_octaves,
                "uShapeCells": (self.cells_g, self.cells_b, self.cells_a),
                "uShapeWorleyOctaves": self.worley_octaves, "uShapeGain": float(self.gain)}


@dataclass(frozen=True)
class DetailBake(_BakeSpec):
    """3D detail noise: R/G/B = inverted-Worley fBm of rising frequency, A = 1 exactly
    (glsl/bakes/cloud_detail.glsl)."""

    kind: ClassVar[str] = "detail"
    group: ClassVar[str] = "bake_detail"
    worley_channels: ClassVar[tuple[int, ...]] = (0, 1, 2)

    size: int = _p(32, 8, 256, "texels per side (32 cloud thesis; 64 maritime thesis)", "int",
                   "texels", SPEC_DETAIL)
    seed: int = _p(0, 0, MAX_SEED, "Worley seed (channel seeds seed·8 + 4 + channel)", "int", "",
                   SPEC_DETAIL)
    cells_r: int = _p(2, 1, 64, "R: Worley cells per tile (octave 0)", "int", "cells", SPEC_DETAIL)
    cells_g: int = _p(4, 1, 64, "G: Worley cells per tile (octave 0)", "int", "cells", SPEC_DETAIL)
    cells_b: int = _p(8, 1, 64, "B: Worley cells per tile (octave 0)", "int", "cells", SPEC_DETAIL)
    octaves: int = _p(3, 1, 16, "octaves of each Worley fBm", "int", "",
                      "spec/001 §1.1; spec/001 eq. 3.2")
    gain: float = _p(0.5, 0.0, 1.0, "octave gain G = 2^-H", "float", "",
                     "spec/001 §1.1; spec/001 eq. 3.2")
    normalize: bool = _p(True, doc="stretch R/G/B to [0, 1] by their min and max (spec/001 §6 "
                         "criterion B1)", kind="bool", section="spec/001 §6 (criterion B1)")

    joints: ClassVar[tuple[Joint, ...]] = (Joint(
        ("bake_detail.cells_r", "bake_detail.cells_g", "bake_detail.cells_b"),
        "bake_detail.cells_r < cells_g < cells_b (rising cell counts, R to B)",
        lambda r, g, b: r < g < b),)

    def uniforms(self) -> dict[str, Any]:
        return {"uDetailSeed": self.seed,
                "uDetailCells": (self.cells_r, self.cells_g, self.cells_b),
                "uDetailOctaves": self.octaves, "uDetailGain": float(self.gain)}


#: GLSL's FBM_MAX_OCTAVES (glsl/common/noise_fbm.glsl): the length of uWeatherCells.
WEATHER_MAX_LAYERS = 16


@dataclass(frozen=True)
class WeatherBake(_BakeSpec):
    """2D weather map: tileable Perlin fBm with GradientSimulator's controls; R low coverage,
    G high coverage, B max height, A density (glsl/bakes/weather_map.glsl)."""

    kind: ClassVar[str] = "weather"
    group: ClassVar[str] = "bake_weather"
    dims: ClassVar[int] = 2

    size: int = _p(512, 8, 4096, "texels per side (Resolution)", "int", "texels", SPEC_WEATHER)
    seed: int = _p(0, 0, MAX_SEED, "Perlin permutation seed (0: Perlin's own table)", "int", "",
                   SPEC_WEATHER)
    scale: float = _p(4.0, 1.0, 128.0, "Scale: lattice cells across the map in layer 0 (rounded to "
                      "whole cells per layer so the map tiles)", "float", "cells", SPEC_WEATHER,
                      step=0.5)
    layers: int = _p(5, 1, WEATHER_MAX_LAYERS, "Num Layers: octaves of the fBm", "int", "",
                     SPEC_WEATHER)
    persistence: float = _p(0.5, 0.0, 1.0, "Persistence: amplitude ratio of successive layers",
                            "float", "", SPEC_WEATHER)
    lacunarity: float = _p(2.0, 1.0, 4.0, "Lacunarity: frequency ratio of successive layers",
                           "float", "", SPEC_WEATHER)
    offset_x: float = _p(0.0, 0.0, 1.0, "Offset x: moves the noise, in maps (the map tiles: any "
                         "offset is taken modulo 1)", "float", "maps", SPEC_WEATHER, step=1 / 512)
    offset_y: float = _p(0.0, 0.0, 1.0, "Offset y: moves the noise, in maps (modulo 1)", "float",
                         "maps", SPEC_WEATHER, step=1 / 512)
    contrast: float = _p(2.0, 0.25, 8.0, "gain k of 0.5 + 0.5 k fBm (the fBm's standard deviation "
                         "is ~0.18)", "float", "", "spec/001 §1.1 (Weather map)")
    density: float = _p(0.5, 0.0, 1.0, "A channel mc_d (constant; 0.5 makes spec/001 eq. 4.11's "
                        "× 2 neutral)", "float", "", "spec/001 §1.4; spec/001 eq. 4.11")

    def __post_init__(self):
        # the map tiles, so an offset of a whole map is no offset: wrap before validating, so a
        # scrolling storm front never leaves the range and equal images share one cache key
        for name in ("offset_x", "offset_y"):
            value = getattr(self, name)
            if (isinstance(value, (int, float)) and not isinstance(value, bool)
                    and math.isfinite(value)):
                object.__setattr__(self, name, float(value) % 1.0)
        super().__post_init__()

    def layer_cells(self) -> list[int]:
        """c_i = max(1, ⌊scale · lacunarity^i + 0.5⌋) for every layer slot (length 16)."""
        return [max(1, int(math.floor(self.scale * self.lacunarity**i + 0.5)))
                if i < self.layers else 1
                for i in range(WEATHER_MAX_LAYERS)]

    def wrapped_offset(self) -> tuple[float, float]:
        """The offset in [0, 1) (wrapped at construction: the same image, and float32 keeps
        its precision however far the weather has scrolled)."""
        return (float(self.offset_x) % 1.0, float(self.offset_y) % 1.0)

    def uniforms(self) -> dict[str, Any]:
        return {"uWeatherCells": self.layer_cells(), "uWeatherLayers": self.layers,
                "uWeatherPersistence": float(self.persistence),
                "uWeatherOffset": self.wrapped_offset(),
                "uWeatherContrast": float(self.contrast), "uWeatherDensity": float(self.density)}


KINDS: dict[str, type[_BakeSpec]] = {c.kind: c for c in (ShapeBake, DetailBake, WeatherBake)}


def bake_params() -> list[Param]:
    """Every bake parameter (groups bake_shape, bake_detail, bake_weather), for a ParamSet."""
    return [p for cls in KINDS.values() for p in cls.params()]


def defaults() -> list[_BakeSpec]:
    """The cloud thesis's defaults: shape 128³, detail 32³, weather 512²."""
    return [ShapeBake(), DetailBake(), WeatherBake()]


def maritime() -> list[_BakeSpec]:
    """The maritime thesis's sizes: volume (shape) noise 132³, detail noise 64³ (spec/000 §1.6)."""
    return [ShapeBake(size=132), DetailBake(size=64)]
