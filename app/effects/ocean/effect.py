"""The open sea of the maritime thesis (spec/000 §1.1, §1.2, §1.3): three wave models switchable
live — sine (spec/000 §1.1(a)), a sum of Gerstner waves (spec/000 §1.1(c)) and the cascaded FFT
ocean (Tessendorf; spec/000 §1.1(d) and (e)) — rendered with the sky's reflection probe, the
main light's glitter, foam, an underwater view, and water-height queries for floating objects.

The effect holds five parts (``app/effects/ocean/``), each with its own state:
* ``sea`` (:class:`~.sea.Sea`, ``sea.py``) — the simulation: the sea state per model, the FFT
  cascades and their GPU simulation (``fft.py``, its schedule ``schedule.py``), stepped once a
  frame (:meth:`~.sea.Sea.step`; the bench's copy through the same :meth:`~.sea.Sea.simulate`);
* ``foam`` (:class:`~.foam.Foam`) — the foam's calibration;
* ``queries`` (:class:`~.queries.WaterQueries`) — the frame's ``water`` slot;
* ``uniforms`` (:class:`~.uniforms.Uniforms`) — what the programs are told;
* ``surface`` (:class:`~.surface.Surface`, ``surface.py``) — the mesh (``mesh.py``), forward
  and deferred drawing (``deferred.py``), the wake map, the view from below, the stage.
Parameters: ``params.py``; numpy reference: ``app/sim/ocean.py``. The slots it produces and
reads, with their fallbacks: the table in docs/architecture.md.
"""

from __future__ import annotations

import numpy as np

from ...errors import NaturaError
from ...frame import Stage
from ...gpu import fft as gpu_fft
from ...gpu.programs import ProgramSpec, fullscreen
from ...params import Joint, Param
from ...sim import ocean as oc
from ...sim.sea_plane import cox_munk_mss
from ..base import Effect, Pass
from .fft import BLEND, RESAMPLE
from .foam import Foam
from .params import ocean_params
from .queries import WaterQueries
from .sea import Sea
from .surface import PROGRAMS, Surface, shading_path
from .uniforms import Uniforms

# the GPU simulation's programs (app/effects/ocean/fft.py, app/gpu/fft.py), listed so that
# `natura shaders check` compiles them and their @param annotations are found
SIMULATION = (
    ProgramSpec("ocean/spectrum_evolve", comp="ocean/spectrum_evolve.comp", requires_compute=True),
    ProgramSpec("ocean/ocean_finalize", comp="ocean/ocean_finalize.comp", requires_compute=True),
    ProgramSpec("ocean/direct_sum", comp="ocean/direct_sum.comp", requires_compute=True),
    fullscreen("ocean/spectrum_evolve"), fullscreen("ocean/ocean_finalize"),
    fullscreen("ocean/direct_sum"), BLEND, RESAMPLE,
) + gpu_fft.VARIANTS


class Ocean(Effect):
    name = "ocean"
    title = "Ocean"
    spec = "spec/000"
    programs = PROGRAMS + SIMULATION
    #: water stage seen from above; fog stage near or under the surface (see passes())
    stages = (Stage.WATER, Stage.FOG)
    produces = frozenset({"wind", "water"})
    consumes = {"environment": "optional", "main_light": "optional", "image": "optional",
                "wind": "optional", "wakes": "optional", "dry_mask": "optional"}
    joints = (Joint(("ocean.patch_sizes", "ocean.cascades", "ocean.fft_size"),
                    "falling patch sizes that hold their bands at ocean.fft_size",
                    lambda sizes, count, n: bool(oc.cascade_bands(int(n), sizes[:count]))),)

    @classmethod
    def context_paths(cls, caps, params) -> dict[str, str]:
        from ...gpu.fft import choose_compute

        fft, shading = params["ocean.fft_path"], params["ocean.shading"]
        try:
            fft_path = "compute shaders" if choose_compute(caps, fft, "ocean.fft_path") \
                else "fragment passes"
        except NaturaError as exc:
            fft_path = f"refused: {exc}"
        return {"ocean FFT": f"{fft_path} (ocean.fft_path={fft})",
                "ocean surface": f"{shading_path(caps, shading)} (ocean.shading={shading})"}

    @classmethod
    def python_params(cls) -> list[Param]:
        return ocean_params()

    def __init__(self, gpu, params):
        super().__init__(gpu, params)
        self.sea = Sea(self)
        self.foam = Foam(self, self.sea)
        self.queries = WaterQueries(params, self.sea)
        self.uniforms = Uniforms(self, self.sea, self.foam, self.queries)
        self.surface = Surface(self, self.sea, self.queries, self.uniforms)

    def update(self, frame, dt: float) -> None:
        sea, queries = self.sea, self.queries
        queries.time = frame.time
        queries.camera_pos = np.asarray(frame.camera.position, dtype=float)
        sea.set_wind(frame)
        if sea.prepare(frame):
            queries.forget()
        if sea.sim is not None:  # the FFT: simulated once a frame, read back a frame late
            queries.take(sea.step(frame, dt, self.foam.thresholds(), queries.query_time))
        else:
            queries.query_time = frame.time
        frame.water = queries
        self.surface.place_camera()

    lesson_param = "ocean.model"  # LESSONS: what panel_notes begins with too
    LESSONS = {
        "sine": "Sine (spec/000 §1.1(a)): one wave with analytic normals — cheap, but it repeats "
                "every wavelength and a lone sine never looks like the sea.",
        "gerstner": "Gerstner (spec/000 §1.1(c)): waves drawn from the spectrum, crests sharpened "
                    "by horizontal motion; each wave's steepness s = k·A must stay ≤ 1 or the "
                    "crests loop.",
        "fft": "FFT (Tessendorf; spec/000 §1.1(d), §1.1(e)): every wave of the spectrum on a "
               "grid, per cascade; choppy displacement, foam where the Jacobian folds; tiles "
               "repeat only at their size.",
    }

    def panel_notes(self) -> list[str]:
        model, sea, sim = self.params["ocean.model"], self.sea, self.sea.sim
        mesh = self.surface.mesh
        lines = [self.LESSONS[model]]
        if sea.frame_wind is not None:
            lines.append(f"wind {sea.frame_wind[0]:.1f} m/s toward {sea.frame_wind[1]:.0f}° from "
                         "the scene's wind (ocean.wind and ocean.wind_direction are not used)")
        lines.append(f"Hs {sea.significant_height():.2f} m · slope variance "
                     f"{sea.resolved_mss:.4f} (Cox–Munk {cox_munk_mss(sea.wind_speed()):.4f})")
        if model == "fft" and sim is not None:
            t = self.queries.query_time
            lines.append(f"N {'/'.join(str(n) for n in sim.sizes)} for {len(sea.patch_sizes())} "
                         f"cascades ({sim.path}); queries lag one frame (t = "
                         f"{t if t is not None else '—'})"
                         + ("" if sea.sim_ran else "; clock standing: not simulated again"))
            if self.params["ocean.simulation"] == "view":
                slow = [f"{i}: every {1e3 * t:.0f} ms" for i, t in enumerate(sim.periods)
                        if t > 0.0]
                lines.append(f"view: smallest footprint {100.0 * sea.footprint:.1f} cm; "
                             + ("snapshots interpolated for cascade " + ", ".join(slow)
                                if slow else "every cascade every frame"))
        if mesh.built:
            lines.append(f"mesh: {mesh.drawn:,} of {mesh.triangles:,} triangles drawn"
                         + ("; camera under water" if self.surface.underwater else ""))
        return lines

    def passes(self, frame, target) -> list[Pass]:
        surface, stage = self.surface, self.surface.stage()
        out = [Pass("ocean.surface", lambda: surface.render(frame, target), stage)]
        if surface.may_be_underwater():
            out.append(Pass("ocean.underwater", lambda: surface.render_underwater(frame, target),
                            stage))
        return out

    def bench_passes(self, frame, target) -> list[Pass]:
        """The passes, after the FFT simulation's update (:meth:`~.sea.Sea.bench_simulate`)."""
        out = self.passes(frame, target)
        if self.sea.sim is not None:
            run = self.sea.bench_simulate(frame.time, self.foam.thresholds())
            out.insert(0, Pass("ocean.simulate", run, self.surface.stage()))
        return out

    def release(self) -> None:
        self.sea.release()
        super().release()
        self.surface.release()
