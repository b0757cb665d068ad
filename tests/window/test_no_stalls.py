"""No stalls in the window's frame (issue 26): over 100 frames of every scene in a real window
under Xvfb, the frame loop (the scene's frame, the display pass, the panel, the HUD, ImGui)
calls no ``ctx.finish()``, reads back no framebuffer, texture or buffer and waits on no query
result — except where documented: the ocean's FFT readback for the boat's buoyancy and the
probes (app/effects/ocean/fft.py, ``request_readback``) copies the displacement into a pixel
buffer on the GPU and maps the *previous* frame's buffer, which is ready by then, so it does
not wait. The counting is done by tests/helpers/stall_driver.py, which wraps moderngl's syncing
calls and names the file and line that called each.
"""

from __future__ import annotations

import json
import sys
from pathlib import Path

import pytest

from app.scenes import SCENES
from tests.helpers.window_driver import NO_XVFB, XVFB_SKIP, under_xvfb

DRIVER = Path(__file__).parent.parent / "helpers" / "stall_driver.py"

pytestmark = [pytest.mark.skipif(NO_XVFB, reason=XVFB_SKIP)]

#: the documented asynchronous readback: (call, the file it is in) — a pixel-buffer copy of the
#: FFT displacement and the read of the buffer copied a frame earlier
ALLOWED = {("Texture.read_into", "app/effects/ocean/fft.py"),
           ("Buffer.read", "app/effects/ocean/fft.py")}
#: the scenes, in two windows' worth of work each (the ocean scenes are the costly ones)
GROUPS = [["sky", "probe", "planet", "clouds", "noise", "materials"],
          ["ocean", "shading", "surfaces"], ["maritime", "village"]]
#: sizes smaller than the defaults, the same calls: the sea on a 64² FFT and a coarser grid (a
#: fifth of the ocean's frame on llvmpipe); the maritime scene's clouds on tiny bakes and 24
#: view steps, its boat without the spin-up (run before the first frame; 9.5 → 3.4 s for 100
#: frames); the planet's shadow map and ground noise at 256² (baked in the warm-up frames:
#: 2.8 → 1.1 s); the village with fewer blades, a coarser island and a smaller shadow map (its
#: multisampled path and every pass kept; 13 → 5.5 s for 100 frames); the surfaces lab's
#: probe and shadow maps smaller (its MSAA kept)
SMALLER = {"ocean": ":ocean.fft_size=64,ocean.mesh_segments=64",
           "maritime": ":ocean.fft_size=64,ocean.mesh_segments=64,clouds_b.volume_resolution=16,"
                       "clouds_b.detail_resolution=8,clouds_b.gradient_resolution=16,"
                       "clouds_b.max_steps=24,boat.spin_up=0",
           "planet": ":planet.shadow_map_size=256,planet.ground_noise_size=256",
           "village": ":grass.blades=20000,village.shadow_map_size=512,village.resolution=65",
           "surfaces": ":surfaces.probe_size=64,surfaces.shadow_map_size=512"}


def test_the_groups_cover_every_scene():
    assert sorted(s for g in GROUPS for s in g) == sorted(SCENES)


@pytest.mark.parametrize("scenes", GROUPS, ids=["+".join(g) for g in GROUPS])
def test_no_frame_waits_for_the_gpu_except_the_fft_readback(tmp_path, scenes):
    args = [scene + SMALLER.get(scene, "") for scene in scenes]
    proc = under_xvfb([sys.executable, str(DRIVER), *args], cwd=tmp_path, timeout=600)
    lines = [line for line in proc.stdout.splitlines() if line.startswith("RESULT ")]
    assert proc.returncode == 0 and lines, proc.stdout[-3000:] + proc.stderr[-3000:]
    result = json.loads(lines[-1][len("RESULT "):])
    assert sorted(result) == sorted(scenes)
    for scene, counted in result.items():
        assert counted["frames"] == 100 and counted["render_error"] is None, (scene, counted)
        stalls = [(what, where, n) for what, where, n in counted["calls"]
                  if (what, where.rsplit(":", 1)[0]) not in ALLOWED]
        assert stalls == [], f"{scene}: the frame waits for the GPU at {stalls}"
        for what, where, n in counted["calls"]:  # the FFT's: at most once per texture a frame
            assert n <= 3 * counted["frames"], (scene, what, where, n)
    # the counting counts: the scenes that float things on the FFT sea read it every frame
    for scene in {"ocean", "maritime"} & set(scenes):
        reads = sum(n for what, _, n in result[scene]["calls"] if what == "Buffer.read")
        assert reads >= result[scene]["frames"], (scene, result[scene]["calls"])
