"""The day–night cycle of the maritime thesis (spec/000 §1.7, ``SkyboxController.cs``).

Per frame: advance the hour, wrap it into [0, 24), rotate sun and moon about the ecliptic axis,
pick the sky-colour keyframes around the hour, and choose the main light (sun by day, moon by
night). Everything here is numpy; ``app.effects.sky`` pushes it to the GPU.

Sky keyframes (one every three hours in the thesis, fig. 4.11) live in a TOML file, each with
a colour gradient over elevation. Colours are written as sRGB hex (as a colour picker shows
them) and used as linear RGB.
"""

from __future__ import annotations

import math
import tomllib
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..colour import srgb_to_linear
from ..errors import ParamError
from ..params import show

GRADIENT_TEXELS = 256


def wrap_hour(hour: float) -> float:
    """Time always stays in [0, 24) (the thesis guards against "hora 25")."""
    h = math.fmod(float(hour), 24.0)
    if h < 0.0:
        h += 24.0
    return 0.0 if h >= 24.0 else h


def _unit(v) -> np.ndarray:
    v = np.asarray(v, dtype=np.float64)
    n = np.linalg.norm(v)
    if not np.isfinite(n) or n < 1e-9:
        raise ParamError(f"sky.ecliptic={show(v)} is the zero vector: allowed any non-zero axis")
    return v / n


def sun_direction(hour: float, ecliptic) -> np.ndarray:
    """Unit vector toward the sun: a rotation about the ecliptic axis, one turn per 24 h.

    Highest at noon (in the plane of the axis and the zenith), lowest at midnight; with an
    axis tilted up toward the north (−z) the sun rises in the east (+x) at 6 h.
    """
    axis = _unit(ecliptic)
    up = np.array([0.0, 1.0, 0.0])
    noon = up - np.dot(up, axis) * axis
    if np.linalg.norm(noon) < 1e-6:  # axis vertical: the sun circles the horizon
        noon = np.array([0.0, 0.0, 1.0]) - axis[2] * axis
    noon /= np.linalg.norm(noon)
    phi = (wrap_hour(hour) - 12.0) / 24.0 * 2.0 * math.pi
    d = math.cos(phi) * noon - math.sin(phi) * np.cross(axis, noon)
    return d / np.linalg.norm(d)


def world_to_moon(moon_dir: np.ndarray, ecliptic) -> np.ndarray:
    """Rows (right, up, toward-moon): the thesis's ``_MoonWorld2Obj`` rotation."""
    f = moon_dir / np.linalg.norm(moon_dir)
    ref = _unit(ecliptic)
    if abs(np.dot(ref, f)) > 0.999:
        ref = np.array([0.0, 1.0, 0.0]) if abs(f[1]) < 0.999 else np.array([1.0, 0.0, 0.0])
    right = np.cross(ref, f)
    right /= np.linalg.norm(right)
    up = np.cross(f, right)
    return np.stack([right, up, f])


# Beyond the thesis (its _SunCol is one constant colour, spec/000 §1.7): the direct sunlight
# through m air masses keeps exp(−τ·m) of its value outside the atmosphere (Beer–Lambert), per
# channel, τ the zenith optical depth at sea level: Rayleigh + aerosol at one wavelength each.

#: the wavelengths (µm) the R, G and B channels stand for
RGB_WAVELENGTHS_UM = (0.680, 0.550, 0.440)
#: Ångström turbidity β (aerosol optical depth at 1 µm) and exponent α of clear maritime air:
#: τ_aerosol(550 nm) ≈ 0.09, a clean-ocean value of sun-photometer climatologies
AEROSOL_BETA = 0.05
AEROSOL_ALPHA = 1.0


def rayleigh_optical_depth(wavelength_um):
    """Zenith Rayleigh optical depth of the standard sea-level atmosphere at ``wavelength_um``
    (µm): τ = 0.008569 λ⁻⁴ (1 + 0.0113 λ⁻² + 0.00013 λ⁻⁴), the fit of Hansen & Travis 1974
    (0.097 at 550 nm)."""
    lam = np.asarray(wavelength_um, dtype=np.float64)
    return 0.008569 * lam**-4 * (1.0 + 0.0113 * lam**-2 + 0.00013 * lam**-4)


def aerosol_optical_depth(wavelength_um, beta: float = AEROSOL_BETA,
                          alpha: float = AEROSOL_ALPHA):
    """Zenith aerosol optical depth τ = β λ^−α (Ångström 1929's turbidity law, λ in µm)."""
    return beta * np.asarray(wavelength_um, dtype=np.float64) ** -alpha


def zenith_optical_depth(beta: float = AEROSOL_BETA, alpha: float = AEROSOL_ALPHA
                         ) -> tuple[float, float, float]:
    """Rayleigh + aerosol zenith optical depth at the R, G, B wavelengths (3 decimals): the
    default ``sky.sun_extinction``, (0.115, 0.188, 0.356) for clear maritime air."""
    lam = np.asarray(RGB_WAVELENGTHS_UM)
    tau = rayleigh_optical_depth(lam) + aerosol_optical_depth(lam, beta, alpha)
    return (round(float(tau[0]), 3), round(float(tau[1]), 3), round(float(tau[2]), 3))


DEFAULT_SUN_EXTINCTION = zenith_optical_depth()


def air_mass(elevation_deg: float) -> float:
    """Relative optical air mass toward a body ``elevation_deg`` above the horizon: Kasten &
    Young 1989, m = 1 / (sin h + 0.50572 (h + 6.07995°)^−1.6364), 1 at the zenith and ≈ 38 at
    the horizon; h is clamped at −1° (the formula's pole is at −6.08°)."""
    h = max(float(elevation_deg), -1.0)
    return 1.0 / (math.sin(math.radians(h)) + 0.50572 * (h + 6.07995) ** -1.6364)


def light_fade(sin_elevation: float) -> float:
    """Main-light strength near the horizon: a smooth ramp from 0 (sun 2° below the horizon)
    to 1 (4.6° above), so the switch between sun and moon never pops."""
    t = min(1.0, max(0.0, (sin_elevation + 0.035) / 0.115))
    return t * t * (3.0 - 2.0 * t)


@dataclass
class Light:
    """A directional light. ``direction`` points from the scene toward the light."""

    name: str
    direction: np.ndarray
    color: tuple[float, float, float]
    intensity: float
    #: the sky's ambient radiance at this hour, when a sky made the light (the cosine-weighted
    #: mean radiance of its upper hemisphere: :meth:`Keyframes.ambient_at`); None: none given
    ambient: tuple[float, float, float] | None = None

    @property
    def radiance(self) -> np.ndarray:
        return np.asarray(self.color) * self.intensity


@dataclass
class Keyframe:
    hour: float
    gradient: list[tuple[float, np.ndarray]]  # (elevation in [0, 1], linear RGB), sorted
    stars: float = 1.0

    def evaluate(self, u: np.ndarray) -> np.ndarray:
        """Piecewise-linear colour at elevations ``u`` (clamped to the first/last stop)."""
        pos = np.array([p for p, _ in self.gradient])
        cols = np.stack([c for _, c in self.gradient])
        u = np.clip(np.asarray(u, dtype=np.float64), 0.0, 1.0)
        return np.stack([np.interp(u, pos, cols[:, k]) for k in range(3)], axis=-1)


def _colour(value, where: str) -> np.ndarray:
    if isinstance(value, str):
        text = value.strip()
        if len(text) == 7 and text.startswith("#"):
            try:
                srgb = [int(text[i : i + 2], 16) / 255.0 for i in (1, 3, 5)]
            except ValueError:
                srgb = None
            if srgb is not None:
                return srgb_to_linear(np.array(srgb))
    raise ParamError(f"{where}: colour {value!r} is not allowed: allowed \"#rrggbb\" (sRGB hex)")


@dataclass
class Keyframes:
    frames: list[Keyframe]
    source: str = ""
    version: int = 0  # bumped on every edit (the UI edits in place)

    @classmethod
    def load(cls, path: Path) -> "Keyframes":
        where = str(path)
        try:
            data = tomllib.loads(Path(path).read_text(encoding="utf-8"))
        except FileNotFoundError:
            raise ParamError(f"sky keyframes {where!r} do not exist: "
                             "allowed a TOML file like resources/sky/keyframes.toml") from None
        except tomllib.TOMLDecodeError as exc:
            raise ParamError(f"sky keyframes {where!r} are not valid TOML: {exc}") from None
        return cls.from_dict(data, where)

    @classmethod
    def from_dict(cls, data: dict, where: str = "keyframes") -> "Keyframes":
        raw = data.get("keyframe")
        if not isinstance(raw, list) or not raw:
            raise ParamError(f"{where}: no [[keyframe]] tables: "
                             "allowed one or more, each with hour and gradient")
        frames = []
        for i, kf in enumerate(raw):
            at = f"{where}: keyframe {i + 1}"
            hour = kf.get("hour")
            if not isinstance(hour, (int, float)) or not 0 <= hour < 24:
                raise ParamError(f"{at}: hour {hour!r} is not allowed: allowed a number in [0, 24)")
            stops = kf.get("gradient")
            if not isinstance(stops, list) or not stops:
                raise ParamError(f"{at}: gradient is missing: "
                                 "allowed a list of [elevation, \"#rrggbb\"]")
            grad = []
            for stop in stops:
                if not (isinstance(stop, list) and len(stop) == 2
                        and isinstance(stop[0], (int, float)) and 0 <= stop[0] <= 1):
                    raise ParamError(f"{at}: gradient stop {stop!r} is not allowed: "
                                     "allowed [elevation in [0, 1], \"#rrggbb\"]")
                grad.append((float(stop[0]), _colour(stop[1], at)))
            grad.sort(key=lambda s: s[0])
            stars = kf.get("stars", 1.0)
            if not isinstance(stars, (int, float)) or not 0 <= stars <= 1:
                raise ParamError(f"{at}: stars {stars!r} is not allowed: "
                                 "allowed a number in [0, 1]")
            frames.append(Keyframe(float(hour), grad, float(stars)))
        frames.sort(key=lambda k: k.hour)
        hours = [k.hour for k in frames]
        if len(set(hours)) != len(hours):
            raise ParamError(f"{where}: two keyframes share an hour: allowed distinct hours")
        return cls(frames, where)

    def to_toml(self) -> str:
        from ..colour import linear_to_srgb

        def hexcol(c):
            s = np.round(linear_to_srgb(np.asarray(c)) * 255).astype(int)
            return "#" + "".join(f"{int(v):02x}" for v in s)

        lines = [
            "# Sky colour by elevation, one keyframe every three hours (spec/000 §1.7, fig. 4.11).",
            "# gradient: [elevation, colour] stops; elevation 0 = horizon, 1 = zenith; "
            "colours sRGB hex.",
            "# stars: how much of the star field shows (multiplies sky.star_intensity).",
        ]
        for k in self.frames:
            lines.append("\n[[keyframe]]")
            lines.append(f"hour = {k.hour:g}")
            lines.append(f"stars = {k.stars:g}")
            stops = ", ".join(f'[{p:g}, "{hexcol(c)}"]' for p, c in k.gradient)
            lines.append(f"gradient = [{stops}]")
        return "\n".join(lines) + "\n"

    def bracket(self, hour: float) -> tuple[int, int, float]:
        """Indices of the keyframes before and after ``hour`` (wrapping midnight) and the
        blend weight of the second."""
        h = wrap_hour(hour)
        hours = [k.hour for k in self.frames]
        n = len(hours)
        if n == 1:
            return 0, 0, 0.0
        after = next((i for i, kh in enumerate(hours) if kh > h), None)
        if after is None:  # past the last keyframe: blend toward the first, next day
            i0, i1 = n - 1, 0
            span = hours[0] + 24.0 - hours[-1]
        elif after == 0:  # before the first keyframe: blend from the last, previous day
            i0, i1 = n - 1, 0
            span = hours[0] + 24.0 - hours[-1]
            h += 24.0
        else:
            i0, i1 = after - 1, after
            span = hours[i1] - hours[i0]
        t = (h - hours[i0]) / span
        return i0, i1, float(min(1.0, max(0.0, t)))

    def stars_at(self, hour: float) -> float:
        i0, i1, t = self.bracket(hour)
        return (1 - t) * self.frames[i0].stars + t * self.frames[i1].stars

    def ambient_at(self, hour: float, samples: int = 8) -> np.ndarray:
        """The gradient's ambient radiance on a horizontal surface, (1/π)∫ L cosθ dω over the
        upper hemisphere: ``samples`` elevations, midpoint rule, weights sin 2·elevation
        normalised. The sky shader's sea and the clouds take it as a uniform (``uSkyAmbient``)."""
        el = (np.arange(samples) + 0.5) / samples * (math.pi / 2)
        w = np.sin(2.0 * el)
        colours = self.gradient_at(el / (math.pi / 2), hour)
        return (w[:, None] * colours).sum(axis=0) / w.sum()

    def texture_data(self) -> np.ndarray:
        """``(n_keyframes, GRADIENT_TEXELS, 4)`` float32: texel i of row k is keyframe k's
        gradient at elevation i / (texels − 1). The GPU interpolates along elevation by linear
        filtering and across hours by mixing two rows (the thesis's suggested GPU move)."""
        u = np.linspace(0.0, 1.0, GRADIENT_TEXELS)
        rows = [np.concatenate([k.evaluate(u), np.ones((GRADIENT_TEXELS, 1))], axis=1)
                for k in self.frames]
        return np.stack(rows).astype(np.float32)

    def gradient_at(self, elevation_u: np.ndarray, hour: float) -> np.ndarray:
        """Numpy twin of the shader's gradient lookup: texels, linear filtering, hour mix."""
        tex = self.texture_data()[..., :3].astype(np.float64)
        x = np.clip(np.asarray(elevation_u, dtype=np.float64), 0.0, 1.0) * (GRADIENT_TEXELS - 1)
        i = np.clip(np.floor(x).astype(int), 0, GRADIENT_TEXELS - 2)
        f = (x - i)[..., None]
        i0, i1, t = self.bracket(hour)

        def row(k):
            return tex[k][i] * (1 - f) + tex[k][i + 1] * f

        return (1 - t) * row(i0) + t * row(i1)


@dataclass
class DayNightState:
    hour: float
    sun_dir: np.ndarray
    moon_dir: np.ndarray
    world_to_moon: np.ndarray
    sun: Light
    moon: Light
    main_light: Light
    keyframe_rows: tuple[int, int, float]
    stars: float


@dataclass
class DayNight:
    """``SkyboxController`` without the rendering: hour, lights and keyframe blend."""

    keyframes: Keyframes
    hour: float = 12.0
    ecliptic: tuple[float, float, float] = (0.0, 0.6, -1.0)
    speed: float = 0.25  # hours per second of animation
    playing: bool = False
    sun_color: tuple[float, float, float] = (1.0, 1.0, 1.0)
    moon_color: tuple[float, float, float] = (1.0, 1.0, 1.0)
    moon_light: float = 0.08
    #: zenith optical depths (R, G, B) that redden the sun; (0, 0, 0) = the thesis's constant
    sun_extinction: tuple[float, float, float] = DEFAULT_SUN_EXTINCTION

    def sun_transmittance(self, sin_elevation: float) -> np.ndarray:
        """exp(−τ·(m − 1)) per channel: the sun's colour through m air masses
        (:func:`air_mass`), relative to the zenith (so the thesis's _SunCol is the colour of
        the sun overhead), for zenith optical depths τ (:func:`zenith_optical_depth`)."""
        tau = np.asarray(self.sun_extinction, dtype=float)
        if not np.any(tau):
            return np.ones(3)
        m = air_mass(math.degrees(math.asin(max(-1.0, min(1.0, sin_elevation)))))
        return np.exp(-tau * (m - 1.0))

    def advance(self, dt: float) -> None:
        if self.playing:
            self.hour = wrap_hour(self.hour + self.speed * dt)
        else:
            self.hour = wrap_hour(self.hour)

    def state(self) -> DayNightState:
        sun = sun_direction(self.hour, self.ecliptic)
        moon = -sun  # opposite the sun, as in the thesis
        sun_color = tuple(float(c)
                          for c in np.asarray(self.sun_color) * self.sun_transmittance(sun[1]))
        ambient = tuple(float(c) for c in self.keyframes.ambient_at(self.hour))
        sun_light = Light("sun", sun, sun_color, light_fade(sun[1]), ambient)
        moon_light = Light("moon", moon, self.moon_color, self.moon_light * light_fade(moon[1]),
                           ambient)
        main = sun_light if sun[1] >= moon[1] else moon_light
        return DayNightState(
            hour=self.hour,
            sun_dir=sun,
            moon_dir=moon,
            world_to_moon=world_to_moon(moon, self.ecliptic),
            sun=sun_light,
            moon=moon_light,
            main_light=main,
            keyframe_rows=self.keyframes.bracket(self.hour),
            stars=self.keyframes.stars_at(self.hour),
        )


def hour_label(hour: float) -> str:
    minutes = int(round(wrap_hour(hour) * 60.0)) % 1440
    return f"{minutes // 60:02d}:{minutes % 60:02d}"
