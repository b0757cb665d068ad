"""GPU FFT ocean (app/gpu/fft.py, app/effects/ocean/fft.py, glsl/ocean/) against the numpy
reference app/sim/ocean.py — spec/000 §1.1(d)–(e) (Tessendorf spectrum, eq. 2.11 with the
conjugate, choppy displacement, spectral derivatives, cascades) and §1.3 (asynchronous readback).

Both paths run every check: compute shaders (GL ≥ 4.3) and the GL 3.3 fragment passes.

Tolerances (measured on llvmpipe, float32 on the GPU against float64 numpy; max abs error
divided by the field's max |value|):
* GpuFFT alone, random data, N = 4…256: ≤ 2.0e-7 → FFT_TOL = 1e-6.
* Ocean fields vs ``synthesize``, N = 32/64/128, 1–3 cascades: ≤ 1.3e-6 (J: relative to
  max |J − 1|) → FIELD_TOL = 1e-5.  At t = 1 day + 0.37 s: 1.5e-6 (the split-phase guard;
  plain float32 ωt would be off by ~0.2 rad there).
* Direct sum vs FFT (two float32 methods): ≤ 3e-6 → DIRECT_TOL = 2e-5.
* Foam vs a chain of ``foam_step`` calls: inherits J's error / threshold → FOAM_TOL = 1e-4 abs.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from app.effects.ocean.fft import GpuOceanSim
from app.errors import ParamError
from app.gpu.fft import GpuFFT
from app.runtime import scene_params
from app.sim import ocean as oc
from tests.helpers.ocean import (
    FIELD_TOL,
    FIELDS,
    PATHS,
    fields_at,
    make_sim,
    reference,
    relative_error,
    worst_errors,
)
from tests.helpers.ocean_sim import ocean_from_cascades

FFT_TOL = 1e-6
DIRECT_TOL = 2e-5
FOAM_TOL = 1e-4


# -- GpuFFT alone ------------------------------------------------------------------------------

@pytest.mark.parametrize("use_compute", PATHS)
@pytest.mark.parametrize("n", [4, 8, 16, 32, 64, 128, 256])
def test_fft_matches_numpy_ifft2(gpu, use_compute, n):
    count = 3 if n == 16 else 2  # an odd count once: MRT with three attachments
    fft = GpuFFT(gpu, "fft-test", n, count=count, use_compute=use_compute)
    rng = np.random.default_rng(n)
    data = [rng.standard_normal((n, n, 4)).astype(np.float32) for _ in range(count)]
    for i, d in enumerate(data):
        fft.textures[i].write(np.ascontiguousarray(d, dtype=np.float32).tobytes())
    fft.inverse()
    for i, d in enumerate(data):
        out = fft.read(i)
        for c in (0, 2):  # the two complex numbers of a texel
            z = d[..., c].astype(np.float64) + 1j * d[..., c + 1]
            ref = np.fft.ifft2(z) * n * n
            got = out[..., c] + 1j * out[..., c + 1].astype(np.float64)
            assert np.max(np.abs(got - ref)) / np.max(np.abs(ref)) < FFT_TOL
    fft.release()
    assert gpu.owned_by("fft-test") == []


@pytest.mark.parametrize("bad", [0, 2, 3, 48, 2048, 2.0, "64", True])
def test_bad_fft_size_is_a_param_error(gpu, bad):
    with pytest.raises(ParamError, match="power of two") as err:
        GpuFFT(gpu, "fft-test", bad)
    assert "\n" not in str(err.value)


def test_a_grid_size_not_a_power_of_two_is_refused_by_the_sim(gpu):
    ocean = reference(32, (60.0,))
    sim = GpuOceanSim(gpu, "ocean-test")
    with pytest.raises(ParamError, match="power of two"):
        sim.set_spectrum(ocean.cascades, 48)
    sim.release()


@pytest.mark.parametrize("bad", ["ocean.cascades=5", "ocean.cascades=0", "ocean.fft_size=48",
                                 "ocean.choppiness=9", "ocean.foam_threshold=0",
                                 "ocean.foam_decay=0"])
def test_bad_simulation_settings_are_refused_by_their_parameters(bad):
    # the simulation's inputs come from these parameters: their ranges are what a user meets
    with pytest.raises(ParamError, match=bad.split("=")[0]) as err:
        scene_params("ocean", sets=[bad])
    assert "\n" not in str(err.value)


# -- the ocean fields ------------------------------------------------------------------------

CASES = [
    pytest.param(32, (60.0,), id="N32x1"),
    pytest.param(64, (120.0, 30.0), id="N64x2"),
    pytest.param(128, (250.0, 40.0, 9.0), id="N128x3"),
]


@pytest.mark.parametrize("use_compute", PATHS)
@pytest.mark.parametrize("n, sizes", CASES)
def test_fields_match_numpy_synthesize(gpu, use_compute, n, sizes):
    ocean = reference(n, sizes)
    sim = make_sim(gpu, ocean, use_compute)
    t = 7.3
    sim.update(t, 1.0, 1.0 / 30.0)
    worst = worst_errors(sim, fields_at(ocean, t))
    assert max(worst.values()) < FIELD_TOL, worst
    assert sim.time == t and sim.sizes == [n] * len(sizes) and sim.patch_sizes == list(sizes)
    assert len(sim.disp) == len(sim.deriv) == len(sim.foam) == len(sizes)
    sim.release()
    assert gpu.owned_by("ocean-test") == []


@pytest.mark.parametrize("use_compute", PATHS)
def test_phase_stays_exact_after_a_day(gpu, use_compute):
    """ω·t in float32 would jitter by ~0.2 rad at t = 1 day; the hi/lo split keeps it exact."""
    ocean = reference(32, (60.0,))
    sim = make_sim(gpu, ocean, use_compute)
    t = 86400.37
    sim.update(t, 1.0, 0.0)
    worst = worst_errors(sim, fields_at(ocean, t))
    assert max(worst.values()) < FIELD_TOL, worst
    sim.release()


@pytest.mark.parametrize("use_compute", PATHS)
def test_direct_sum_matches_fft(gpu, use_compute):
    ocean = reference(32, (60.0, 20.0))
    sim = make_sim(gpu, ocean, use_compute)
    t = 4.1
    sim.update(t, 1.0, 0.0)
    fft_fields = [sim.read_fields(i) for i in range(2)]
    sim.direct_sum(t, 1.0)
    assert sim.time == t
    assert all(0 < m <= 32 * 32 for m in sim.mode_counts())
    for i, ref in enumerate(fft_fields):
        got = sim.read_fields(i)
        for key in FIELDS:
            assert relative_error(got[key], ref[key], key) < DIRECT_TOL, (i, key)
        np.testing.assert_array_equal(got["foam"], ref["foam"])  # direct_sum leaves foam alone
    sim.release()


def test_tiling_and_mipmaps(gpu):
    """The fields are periodic: the step across the wrap is like any interior step, and the
    textures repeat and carry mipmaps."""
    ocean = reference(64, (120.0, 30.0))
    sim = make_sim(gpu, ocean, None)
    sim.update(2.0, 1.0, 0.0)
    for i in range(2):
        f = sim.read_fields(i)
        for key in ("height", "disp_x", "disp_z", "slope_x"):
            a = f[key]
            for axis in (0, 1):
                inner = np.abs(np.diff(a, axis=axis))
                wrap = np.abs(np.take(a, 0, axis=axis) - np.take(a, -1, axis=axis))
                assert wrap.max() <= 1.5 * inner.max(), (i, key, axis)
                assert wrap.mean() <= 2.0 * inner.mean(), (i, key, axis)
        for tex in (sim.disp[i], sim.deriv[i]):
            assert tex.repeat_x and tex.repeat_y
            assert tex.filter[0] == 0x2703  # GL_LINEAR_MIPMAP_LINEAR
            lvl0 = np.frombuffer(tex.read(level=0), np.float32).reshape(64, 64, 4)
            lvl1 = np.frombuffer(tex.read(level=1), np.float32).reshape(32, 32, 4)
            box = lvl0.reshape(32, 2, 32, 2, 4).mean(axis=(1, 3))
            np.testing.assert_allclose(lvl1, box, atol=1e-5 * np.abs(lvl0).max())
    sim.release()


# -- foam ------------------------------------------------------------------------------------

STEEP = dict(n=32, sizes=(40.0,), wind=15.0)


@pytest.mark.parametrize("use_compute", PATHS)
def test_foam_appears_where_the_jacobian_is_below_threshold(gpu, use_compute):
    ocean = reference(STEEP["n"], STEEP["sizes"], STEEP["wind"])
    sim = make_sim(gpu, ocean, use_compute)
    thr = 0.5
    sim.update(3.0, 2.5, 0.1, foam_threshold=thr)
    f = sim.read_fields(0)
    j, foam = f["jacobian"], f["foam"]
    below, above = j < thr - 1e-4, j > thr + 1e-4
    assert below.sum() > 5 and above.sum() > 5  # the steep sea folds somewhere, not everywhere
    assert np.all(foam[below] > 0)
    assert np.all(foam[above] == 0)
    np.testing.assert_allclose(foam, np.clip((thr - j) / thr, 0, 1), atol=1e-6)
    sim.release()


@pytest.mark.parametrize("use_compute", PATHS)
def test_foam_accumulates_and_decays_like_foam_step(gpu, use_compute):
    ocean = reference(STEEP["n"], STEEP["sizes"], STEEP["wind"])
    sim = make_sim(gpu, ocean, use_compute)
    thr, tau, dt = 0.6, 1.5, 0.25
    foam_ref = np.zeros((STEEP["n"], STEEP["n"]))
    # five frames with breaking waves, then three calm frames (λ = 0 → J = 1: pure decay)
    schedule = [(2.5, i * dt) for i in range(5)] + [(0.0, (5 + i) * dt) for i in range(3)]
    for lam, t in schedule:
        sim.update(t, lam, dt, foam_threshold=thr, foam_decay_time=tau)
        jac = fields_at(ocean, t, lam)[0].jacobian
        foam_ref = oc.foam_step(foam_ref, jac, dt, threshold=thr, decay_time=tau)
        got = sim.read_fields(0)["foam"]
        assert np.max(np.abs(got - foam_ref)) < FOAM_TOL, (lam, t)
    assert foam_ref.max() > 0.2  # the check saw foam, and it is decaying, not gone
    # dt ≤ 0: no decay, no NaN
    before = sim.read_fields(0)["foam"]
    for bad_dt in (0.0, -1.0, float("nan")):
        sim.update(10.0, 0.0, bad_dt, foam_threshold=thr, foam_decay_time=tau)
        np.testing.assert_array_equal(sim.read_fields(0)["foam"], before)
    sim.release()


# -- readback --------------------------------------------------------------------------------

@pytest.mark.parametrize("use_compute", PATHS)
def test_async_readback_lags_one_request(gpu, use_compute):
    ocean = reference(32, (60.0, 20.0))
    sim = make_sim(gpu, ocean, use_compute)
    assert sim.poll_readback() is None
    sim.update(1.0, 1.0, 0.1)
    first = [sim.read_fields(i) for i in range(2)]
    sim.request_readback()
    assert sim.poll_readback() is None  # only this frame's request exists: not read yet
    sim.update(2.0, 1.0, 0.1)
    second = [sim.read_fields(i) for i in range(2)]
    sim.request_readback()
    t, arrays = sim.poll_readback()
    assert t == 1.0 and len(arrays) == 2
    for arr, f in zip(arrays, first):
        assert arr.shape == (32, 32, 4) and arr.dtype == np.float32
        np.testing.assert_array_equal(arr[..., 0], f["disp_x"])
        np.testing.assert_array_equal(arr[..., 1], f["height"])
        np.testing.assert_array_equal(arr[..., 2], f["disp_z"])
        np.testing.assert_array_equal(arr[..., 3], f["jacobian"])
    assert sim.poll_readback()[0] == 1.0  # no new request: the same result again
    sim.update(3.0, 1.0, 0.1)
    sim.request_readback()
    t, arrays = sim.poll_readback()
    assert t == 2.0
    np.testing.assert_array_equal(arrays[1][..., 1], second[1]["height"])
    sim.release()


def test_set_spectrum_reallocates_only_on_size_change(gpu):
    """A cascade's textures are remade only when its own N changes: a new sea of the same
    sizes, or one cascade fewer, keeps the others'."""
    a = reference(32, (60.0, 20.0))
    sim = make_sim(gpu, a, None)
    disp = list(sim.disp)
    sim.update(1.0, 1.0, 0.1)
    b = reference(32, (60.0, 20.0), seed=11)
    sim.set_spectrum(b.cascades, 32)
    assert all(x is y for x, y in zip(sim.disp, disp))
    sim.update(1.0, 1.0, 0.1)
    worst = worst_errors(sim, fields_at(b, 1.0))
    assert max(worst.values()) < FIELD_TOL
    sim.set_spectrum(b.cascades[:1], 32)
    assert len(sim.disp) == 1 and sim.disp[0] is disp[0]
    sim.set_spectrum([b.cascades[0], oc.crop_cascade(b.cascades[1], 16)])
    assert sim.sizes == [32, 16] and sim.disp[0] is disp[0] and sim.disp[1] is not disp[1]
    assert {a.kind for a in gpu.owned_by("ocean-test")} >= {"texture", "program"}
    sim.release()
    assert gpu.owned_by("ocean-test") == []


# -- what the view resolves: cascades of their own N, slow cascades (issue 37) ----------------

BLEND_KEYS = ("height", "disp_x", "disp_z", "slope_x", "slope_z", "ddx_dx", "ddz_dz",
              "jacobian")


def _blend_errors(sim, i: int, ref_a, ref_b, w: float) -> dict[str, float]:
    got = sim.read_fields(i)
    return {key: relative_error(got[key], (1.0 - w) * getattr(ref_a, key)
                                + w * getattr(ref_b, key), key) for key in BLEND_KEYS}


@pytest.mark.parametrize("use_compute", PATHS)
def test_cascades_of_their_own_size_match_numpy(gpu, use_compute):
    """Each cascade on a grid of its own (the view's choice: a crop of the 32² sea) evolves,
    transforms and finalises exactly as the numpy synthesis of the same cropped spectrum."""
    ocean = reference(32, (60.0, 20.0, 6.0))
    cascades = [ocean.cascades[0], oc.crop_cascade(ocean.cascades[1], 16), ocean.cascades[2]]
    sim = GpuOceanSim(gpu, "ocean-test", use_compute=use_compute)
    sim.set_spectrum(cascades)
    assert sim.sizes == [32, 16, 32]
    sim.update(2.7, 1.0, 1.0 / 30.0)
    cropped = ocean_from_cascades(ocean.params, cascades)
    worst = worst_errors(sim, fields_at(cropped, 2.7))
    assert max(worst.values()) < FIELD_TOL, worst
    sim.request_readback()
    _, grids = sim.poll_readback() or sim.read_newest()
    assert [g.shape for g in grids] == [(32, 32, 4), (16, 16, 4), (32, 32, 4)]
    sim.release()
    assert gpu.owned_by("ocean-test") == []


@pytest.mark.parametrize("use_compute", PATHS)
def test_a_slow_cascade_shows_the_blend_of_exact_snapshots(gpu, use_compute):
    """A slow cascade (period T = 0.25 s at frames of 1/32 s, times exact in binary) shows, at
    every frame, the linear blend of the exact seas at t_a and t_a + T with w = (t − t_a)/T —
    its next snapshot computed step by step over the frames before — while a cascade at
    period 0 stays exact at t; the readback for floating objects is the blend that is drawn."""
    ocean = reference(32, (60.0, 20.0))
    sim = make_sim(gpu, ocean, use_compute)
    period, dt, t0 = 0.25, 1.0 / 32.0, 5.0
    sim.set_refresh([period, 0.0])
    assert sim.periods == [period, 0.0]
    refs = {}

    def at(t):
        if t not in refs:
            refs[t] = fields_at(ocean, t)
        return refs[t]

    for k in range(20):  # two swaps and a half
        t = t0 + k * dt
        sim.update(t, 1.0, dt)
        assert sim.last_work == ["snapshots", "fft"]
        t_a = t0 + period * math.floor((t - t0) / period)
        w = (t - t_a) / period
        worst = _blend_errors(sim, 0, at(t_a)[0], at(t_a + period)[0], w)
        assert max(worst.values()) < FIELD_TOL, (k, worst)
        if k in (3, 13):
            exact = worst_errors_one(sim, 1, at(t)[1])
            assert max(exact.values()) < FIELD_TOL, (k, exact)
            sim.request_readback()
            got = sim.read_newest()[1]
            blend = (1.0 - w) * at(t_a)[0].height + w * at(t_a + period)[0].height
            assert relative_error(got[0][..., 1], blend, "height") < FIELD_TOL
    # back to every frame (the thesis): exact at once
    sim.set_refresh([0.0, 0.0])
    sim.update(9.0, 1.0, dt)
    assert max(worst_errors(sim, at(9.0)).values()) < FIELD_TOL
    sim.release()
    assert gpu.owned_by("ocean-test") == []


def worst_errors_one(sim, i: int, ref) -> dict[str, float]:
    got = sim.read_fields(i)
    return {key: relative_error(got[key], getattr(ref, key), key) for key in FIELDS}


def test_a_slow_cascade_starts_over_on_a_new_sea_or_a_jump_in_time(gpu):
    """New amplitudes or a clock that jumps back: the next frame shows the exact sea at t
    (snapshot A computed then), never a blend of snapshots of the old sea or the old time."""
    a = reference(32, (60.0, 20.0))
    b = reference(32, (60.0, 20.0), seed=11)
    sim = make_sim(gpu, a, None)
    sim.set_refresh([0.25, 0.5])
    for k in range(5):
        sim.update(1.0 + k / 32.0, 1.0, 1.0 / 32.0)
    sim.set_spectrum(b.cascades, 32)
    sim.update(1.2, 1.0, 1.0 / 32.0)
    new = fields_at(b, 1.2)[0]
    assert max(_blend_errors(sim, 0, new, new, 0.0).values()) < FIELD_TOL
    sim.update(0.3, 1.0, -0.9)  # back in time
    for i in (0, 1):
        assert max(_blend_errors(sim, i, fields_at(b, 0.3)[i], fields_at(b, 0.3)[i],
                                 0.0).values()) < FIELD_TOL
    sim.release()
