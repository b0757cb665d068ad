"""Live changes do not grow the process: every parameter that re-creates GPU objects (map and
bake sizes, cascade counts, FFT sizes, LUT sizes, grass counts, cubemap sizes, meshes rebuilt
from a value), flipped between two values frame after frame in a live session — the window's
way: ``params.set`` between ``scene.frame`` and ``scene.render``, ``scene.interactive`` on —
leaves as many GL objects after 40 flips as after 2, and the resident memory flat.

Why: each live change of ``village.resolution`` held ~3.5 MB more (251 MB → 770 MB alternating
193 and 150 every frame): the programs' cached vertex arrays kept every freed terrain buffer's
storage in the driver (``Gpu.free`` now releases them). Found the same way: the clouds kept every
bake's texels (8 MB a ``bake_shape`` change), and a change of the boat's simulation dropped its
dry-mask targets without freeing them.

The counts (``tests/helpers/leaks.py``): the context's moderngl objects not released, wherever
Python keeps them, and those dropped without a release (queued by moderngl's ``context_gc``), and
the resources the Gpu records: equal after 2 and after 40 flips (the same value is set then), so
one object more a flip fails (38 more: any count of flips over 2 shows it). The memory: read after
each flip of three windows of ``WINDOW`` flips — the first after flip ``WARM_RSS`` (by then every
build of both values is made and the process's caches of them are filled), one in the middle and
the last — freed heap handed back first. A leak raises the reads in both halves of the run; so the
median of the window must rise by ``RSS_BOUND_MB`` or more from the first window to the middle
*and* again from the middle to the last to fail: 2.5 MB over the 12 and 14 flips between (the
medians of flips 8–14, 20–26 and 34–40), ~0.2 MB a flip, ~18× under the village's leak (3.5 MB a
flip: +45 MB in each half) and ~40× under the clouds' (8 MB a bake). Tried on a scratch copy of
this test (issue 40): 3.5 MB or 0.25 MB kept a flip fails, 0.12 MB passes; one texture kept a flip
fails the count. With 100 flips (until issue 40; 190 s of the suite's time) it was 2.5 MB over ~37
flips, 0.07 MB a flip; the bound is not scaled down with the distance, since the reads of a
leak-free session move by up to ~2 MB between two windows of 7. The windows have an odd count: a
median is one read, never the mean of two levels ~11 MB apart. They start on flips of the same
parity: a value whose memory alternates with the flips (``ocean.fft_size`` by 3.6 MB on a CI run)
is compared with itself, not the low side of one window with the high side of the next. One rise is
not a leak: the process steps between two levels ~11 MB apart, once for good (the village's
``vr.enabled``, 538.6 → 549.4 MB, flat after) or back and forth at random
(``hillaire.skyview_width``, 391.7 ↔ 402.9 MB on a CI run); a single rise of ``RSS_STEP_MB`` (more
than two such steps) fails all the same. Each case renders 32 × 18 frames with the scene's costly
extras off (the boat's spin-up too: a new simulation sails 25 s at once before its first frame);
all are slow (1–8 s a case on llvmpipe); pass and fail depend on counts and bytes only, never on
time."""

from __future__ import annotations

import statistics

import pytest

from app.runtime import open_session, scene_params
from tests.helpers.leaks import gl_objects, rss_mb, watch

pytestmark = pytest.mark.slow

SIZE = (32, 18)
FLIPS = 40
WARM = 2  # flips before the GL objects are counted the first time
WARM_RSS = 7  # flips before the resident memory is read the first time (its windows start even)
WINDOW = 7  # resident memory read after each of this many flips, first after WARM_RSS and last
RSS_BOUND_MB = 2.5  # a rise in each half of the run, median to median (13 flips apart)
RSS_STEP_MB = 24.0  # any rise from the first window to the last

OCEAN = ("ocean.fft_size=64", "sky.cubemap_size=16")
#: the boat without its spin-up (25 s sailed at once, 1.5 s a new simulation): it makes no GL
#: object and holds no memory, and the navigation case makes a new simulation every flip
MARITIME = (*OCEAN, "boat.spin_up=0")
#: the village without what no change here touches: one shadow map of 256² (a step of the hero
#: or a new terrain renders it again: 2048² took 60 ms of llvmpipe a flip), no MSAA, no
#: contours, fewer blades, the free camera (the hero is not walked by it)
VILLAGE = ("grass.blades=2000", "village.shadow_cascades=0", "village.shadow_map_size=256",
           "village.msaa=0", "village.contours=false", "village.camera=free")
#: the surfaces lab with the sun's one shadow map, without MSAA, the probe prefiltered with
#: fewer samples
SURFACES = ("surfaces.shadow_point=false", "surfaces.shadow_spot=false",
            "surfaces.shadow_cascades=0", "surfaces.msaa=0", "surfaces.prefilter_samples=8")

#: (scene, its settings, parameter, two values)
CASES = [
    ("village", VILLAGE, "village.resolution", 193, 150),  # the issue's
    ("village", VILLAGE, "village.shadow_map_size", 64, 128),
    ("village", VILLAGE, "village.hero_x", 0.0, 20.0),  # the hero's buffers, as it walks
    ("village", VILLAGE, "fog.plane_height", 0.35, 0.85),  # the fog plane's mesh and mask
    ("village", VILLAGE, "grass.blades", 2000, 1000),
    ("village", VILLAGE, "grass.seed", 7, 8),
    ("village", VILLAGE, "grass.variety", 1.0, 0.9),  # the billboards' units
    ("village", VILLAGE, "vr.enabled", False, True),  # the eyes' targets
    ("village", (*VILLAGE, "vr.enabled=true"), "vr.render_scale", 1.0, 0.5),
    ("village", (*VILLAGE, "grass.method=instanced"), "grass.segments", 5, 4),
    ("village", (*VILLAGE, "grass.method=instanced"), "grass.lod_segments", 2, 1),
    ("village", (*VILLAGE, "grass.method=instanced"), "grass.blades", 2000, 1000),
    ("village", (*VILLAGE, "grass.method=geometry"), "grass.blades", 2000, 1000),
    ("sky", (), "sky.star_seed", 7, 8),
    ("probe", (), "sky.cubemap_size", 16, 8),
    ("materials", (), "wood.noise_seed", 1, 2),
    ("clouds", (), "bake_shape.seed", 0, 1),  # 128³: 8 MB of texels a bake
    ("clouds", (), "bake_shape.size", 8, 16),
    ("clouds", (), "bake_detail.size", 8, 16),
    ("clouds", (), "bake_weather.size", 8, 16),
    ("clouds", ("scene.model=b",), "clouds_b.volume_resolution", 8, 16),
    ("clouds", ("scene.model=b",), "clouds_b.detail_resolution", 8, 16),
    ("clouds", ("scene.model=b",), "clouds_b.gradient_resolution", 8, 16),
    ("noise", (), "bake_shape.size", 8, 16),
    ("ocean", OCEAN, "ocean.fft_size", "64", "128"),
    ("ocean", OCEAN, "ocean.cascades", 3, 1),
    ("ocean", OCEAN, "ocean.fft_path", "auto", "fragment"),
    ("ocean", OCEAN, "ocean.model", "fft", "gerstner"),
    ("ocean", OCEAN, "ocean.mesh_segments", 32, 33),
    ("maritime", MARITIME, "boat.fittings", True, False),
    ("maritime", MARITIME, "boat.navigation", "rudder", "thesis"),  # a new simulation each
    ("planet", (), "planet.shadow_map_size", 64, 128),
    ("planet", (), "planet.ground_noise_size", 64, 128),
    ("planet", ("planet.method=lut",), "planet.lut_height", 8, 16),
    ("planet", ("planet.method=lut",), "planet.lut_angle", 8, 16),
    ("planet", ("planet.method=hillaire",), "hillaire.transmittance_width", 16, 32),
    ("planet", ("planet.method=hillaire",), "hillaire.ms_size", 4, 8),
    ("planet", ("planet.method=hillaire",), "hillaire.skyview_width", 8, 16),
    ("planet", ("planet.method=hillaire",), "hillaire.ap_size", 4, 8),
    ("shading", (), "shading.shadow_map_size", 64, 128),
    # (the reflection probe is captured again when the shadows change: at its smallest here)
    ("surfaces", (*SURFACES, "surfaces.probe_size=64"), "surfaces.shadow_map_size", 64, 128),
    ("surfaces", SURFACES, "surfaces.probe_size", 64, 128),
]


def _id(case) -> str:
    scene, sets, name = case[:3]
    extra = [s for s in sets if s not in VILLAGE + MARITIME + SURFACES]
    return "-".join([scene, *extra, name])


@pytest.fixture(scope="module")
def sessions():
    """A live session of (scene, settings), on a context of its own (whose objects alone are
    counted), as the window has it: interactive frames. One at a time: the cases of one session
    follow each other, and the one before is released when another is asked for."""
    opened: dict = {}

    def get(scene: str, sets: tuple):
        key = (scene, sets)
        if key not in opened:
            for session, _ in opened.values():
                session.release()
            opened.clear()
            session = open_session(scene, scene_params(scene, sets=sets))
            watch(session.gpu.ctx)
            session.scene.interactive = True
            opened[key] = (session, session.gpu.target("test", "frame", SIZE))
        return opened[key]

    yield get
    for session, _ in opened.values():
        session.release()


@pytest.mark.parametrize("case", CASES, ids=[_id(c) for c in CASES])
def test_a_live_change_flipped_40_times_holds_nothing_more(sessions, case):
    scene, sets, name, a, b = case
    flips, window = FLIPS, WINDOW
    session, target = sessions(scene, tuple(sets))
    params, ctx = session.params, session.gpu.ctx
    before = params[name]
    first_reads = range(WARM_RSS + 1, WARM_RSS + window + 1)  # flips counted from 1
    last_reads = range(flips - window + 1, flips + 1)
    middle = (first_reads[0] + last_reads[-1] - window + 1) // 2
    middle -= (middle - first_reads[0]) % 2  # every window starts on the same parity
    assert (last_reads[0] - first_reads[0]) % 2 == 0
    middle_reads = range(middle, middle + window)
    read_after = set(first_reads) | set(middle_reads) | set(last_reads)
    readings: dict[int, float] = {}

    def flip(i: int) -> None:  # what the window does when the panel changes a value
        params.set(name, (a, b)[i % 2])
        session.scene.render(session.scene.frame(SIZE, 1 / 30), target)
        # the window's buffer swap ends its frame: llvmpipe frees a released texture only once
        # the frames that used it are done (without this, 100 flips of the star seed held
        # 165 MB until the next finish)
        ctx.finish()
        if i + 1 in read_after:
            readings[i + 1] = rss_mb()

    try:
        for i in range(WARM):
            flip(i)
        objects, recorded = gl_objects(ctx), len(session.gpu.allocations)
        for i in range(WARM, flips):
            flip(i)
        objects_after, recorded_after = gl_objects(ctx), len(session.gpu.allocations)
    finally:
        params.set(name, before)
    more = objects_after - objects
    fewer = objects - objects_after
    assert not more and not fewer, (
        f"{name} = {a!r} ↔ {b!r}: {flips} flips hold GL objects {dict(objects_after)}, "
        f"after {WARM} {dict(objects)} (more: {dict(more)}, fewer: {dict(fewer)})")
    assert recorded_after == recorded, (
        f"{name}: {recorded_after} resources recorded by the Gpu after {flips} flips, "
        f"{recorded} after {WARM}")
    # a leak raises the reads in both halves of the run; the process's ~11 MB steps between
    # two levels raise them in one at most (see the module's note)
    windows = [first_reads, middle_reads, last_reads]
    medians = [statistics.median(readings[f] for f in w) for w in windows]
    rises = [medians[1] - medians[0], medians[2] - medians[1]]
    shown = " → ".join(f"{w[0]}–{w[-1]}: {[round(readings[f], 1) for f in w]}" for w in windows)
    assert min(rises) < RSS_BOUND_MB, (
        f"{name} = {a!r} ↔ {b!r}: resident memory rose {rises[0]:.1f} MB and then {rises[1]:.1f} "
        f"MB (median to median; allowed < {RSS_BOUND_MB:g} MB in one of the halves): {shown}")
    assert medians[2] - medians[0] < RSS_STEP_MB, (
        f"{name} = {a!r} ↔ {b!r}: resident memory rose {medians[2] - medians[0]:.1f} MB "
        f"(median to median; allowed < {RSS_STEP_MB:g} MB): {shown}")
