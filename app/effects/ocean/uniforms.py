"""What the ocean's programs are told: the wave model (sine, Gerstner set, FFT cascades and
their textures) and the shading (environment, main light, sub-grid slopes)."""

from __future__ import annotations

import math

import numpy as np

from ...sim import ocean as oc
from ...sim.sea_plane import cox_munk_mss
from .params import MODELS, wind_vector


class Uniforms:
    """Uniforms and textures of the ocean's passes, from its ``sea``, ``foam`` and ``queries``
    (the frame's time and camera)."""

    def __init__(self, effect, sea, foam, queries):
        self.params, self.apply_params = effect.params, effect.apply_params
        self.sea, self.foam, self.queries = sea, foam, queries

    def wave_uniforms(self, prog) -> dict:
        """Set the wave model's uniforms; returns its textures by sampler name (FFT)."""
        p, sea, q = self.params, self.sea, self.queries
        cam = q.camera_pos
        model = MODELS.index(p["ocean.model"])
        fade_start, fade_end = q.fade_range()
        foam_t, foam_w = self.foam.thresholds()[0]
        prog.set_many({"uWaveModel": model, "uTime": float(q.time), "uFadeStart": fade_start,
                       "uFadeEnd": fade_end, "uFoamThreshold": foam_t, "uFoamWidth": foam_w})
        d = wind_vector(sea.wind_direction())
        if model == 0:
            a, k, w = sea.sine_wave()
            phase = math.fmod(k * (d[0] * cam[0] + d[1] * cam[2]), 2.0 * math.pi)
            prog.set("uSine", (float(d[0]), float(d[1]), k, a))
            prog.set("uSinePhase", (-w, phase))
        elif model == 1:
            waves = sea.gerstner_waves()
            a_rows, b_rows = [], []
            for wv in waves:
                dx, dz = np.asarray(wv.direction) / math.hypot(*wv.direction)
                k = 2.0 * math.pi / wv.wavelength
                om = float(oc.dispersion_omega(k, p["ocean.depth"]))
                ph = math.fmod(wv.phase + k * (dx * cam[0] + dz * cam[2]), 2.0 * math.pi)
                a_rows.append((dx, dz, k, wv.steepness / k))
                b_rows.append((om, ph, wv.steepness, 0.0))
            prog.set("uGerstnerCount", len(waves))
            prog.set_array("uGerstnerA", a_rows)
            prog.set_array("uGerstnerB", b_rows)
        else:
            sizes = sea.patch_sizes()
            grids = sea.sim.sizes  # each cascade's N (the view's choice)
            rows = []
            for size, n in zip(sizes + [1.0] * (4 - len(sizes)), grids + [1] * (4 - len(grids))):
                # sample j of the grid sits at j·L/N, i.e. at texel centre (j + ½)/N
                uv = ((cam[0] / size + 0.5 / n) % 1.0, (cam[2] / size + 0.5 / n) % 1.0)
                rows.append((uv[0], uv[1], 1.0 / size, n / size))
            prog.set_array("uCascadeUV", rows)
            bands = sea.cascade_bands + [(1.0, 2.0, 0.0)] * (4 - len(sea.cascade_bands))
            prog.set_array("uCascadeBand", [(lo, hi, m, 0.0) for lo, hi, m in bands])
            weight = p["ocean.foam_amount"]
            prog.set_array("uFoamWeight", [weight] * 4)  # shorter when cascades are left out
            prog.set("uCascades", len(sizes))
            textures = {}
            for kind, held in (("uDisp", sea.sim.disp), ("uDeriv", sea.sim.deriv),
                               ("uFoam", sea.sim.foam)):
                for i in range(4):
                    textures[f"{kind}{i}"] = held[min(i, len(sizes) - 1)]
            return textures
        return {}

    def shading_uniforms(self, prog, frame, env) -> dict:
        """Set the shading uniforms; returns the environment cubemap by sampler name."""
        p, sea = self.params, self.sea
        subgrid = (max(cox_munk_mss(sea.wind_speed()) - sea.resolved_mss, 0.0)
                   if p["ocean.subgrid_slopes"] else 0.0)
        prog.set_many({"uEnvironmentLods": float(max(0, int(math.log2(env.size[0])))),
                       "uSubgridMss": subgrid, "uSeaHs": max(sea.significant_height(), 1e-3)})
        if frame.main_light is not None:
            prog.set_many(frame.light_uniforms())
        else:
            prog.set_many({"uMainLightDir": (0.0, 0.7071, 0.7071),
                           "uMainLightRadiance": (1.0, 1.0, 1.0)})
        self.apply_params(prog)
        return {"uEnvironment": env}

    def surface_uniforms(self, prog, frame, env) -> dict:
        """:meth:`wave_uniforms`, then :meth:`shading_uniforms`: their textures by sampler name."""
        return {**self.wave_uniforms(prog), **self.shading_uniforms(prog, frame, env)}

    def wake_uniforms(self, prog, frame) -> None:
        """The first wake of the frame's ``wakes`` slot (glsl/common/wake.glsl), its samples
        relative to the camera in float64; none: ``uWakeCount`` 0."""
        trail = frame.wakes[0] if frame.wakes else None
        if trail is None or len(trail) == 0:
            prog.set("uWakeCount", 0)
            return
        cam = np.asarray(frame.camera.position, dtype=float)[[0, 2]]
        n = len(trail)
        rel = trail.positions - cam
        samples = np.zeros((64, 4), dtype=np.float32)
        samples[:n, :2] = rel
        samples[:n, 2] = frame.time - trail.times
        samples[:n, 3] = trail.speeds
        dirs = np.zeros((64, 2), dtype=np.float32)
        dirs[:n] = trail.directions
        x0, z0, x1, z1 = trail.bounds(frame.time)
        w = trail.params
        prog.set_array("uWakeSample", samples)
        prog.set_array("uWakeDir", dirs)
        prog.set_many({"uWakeCount": n, "uWakeFirst": 0, "uWakeEnd": n,
                       "uWakeBounds": (x0 - cam[0], z0 - cam[1], x1 - cam[0], z1 - cam[1]),
                       "uWakeShape": (trail.beam, w.cusp_width, w.spacing, w.wash_spread),
                       "uWakeLife": (w.cusp_life, w.wash_life, w.strength)})

    def dry_mask_textures(self, prog, frame) -> dict:
        """The frame's ``dry_mask`` (glsl/common/dry_mask.glsl): its textures by sampler name;
        none: ``uDryMask`` 0 and nothing bound."""
        mask = frame.dry_mask
        prog.set("uDryMask", 0 if mask is None else 1)
        return {} if mask is None else {"uDryFront": mask.front, "uDryBack": mask.back}
