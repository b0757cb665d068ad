"""Regenerate the pictures of docs/commands.md, rendered headless exactly as `natura render` does:
docs/sky.png (the `sky` scene at four hours), docs/materials.png (wood, marble and granite
with the thesis's value noise and with Perlin's gradient noise) and docs/planet.png (the
atmosphere from the ground and from space), docs/clouds.png (the three cloud presets and the
maritime model over the Preetham sky), docs/ocean.png (an evening FFT sea, the sine and Gerstner
waves at noon, and the view from under the water) and docs/village.png (the toon village at ten,
at sunset and at night, and its VR pair).

    python tools/readme_images.py [--force] [--only village.png]
"""

from __future__ import annotations

import argparse
import sys

import numpy as np

from app import PROJECT_ROOT
from app.colour import to_srgb8
from app.runtime import open_session, render_frames, scene_params

SHOTS = [("sky", 6.3, "sunrise"), ("sky", 12.0, "noon"), ("sky", 18.5, "sunset"),
         ("sky", 0.0, "midnight")]


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("--force", action="store_true", help="replace docs/sky.png")
    ap.add_argument("--size", default="480x270")
    ap.add_argument("--only", default=None, help="make only this picture (e.g. village.png)")
    args = ap.parse_args(argv)
    w, h = (int(v) for v in args.size.split("x"))

    def shot(scene, sets, size, camera=None):
        params = scene_params(scene, sets=sets)
        session = open_session(scene, params)
        if camera:
            session.scene.camera.set(**camera)
        image = next(render_frames(session, size))
        exposure = session.scene.exposure()
        session.release()
        return to_srgb8(image[..., :3], exposure, params["output.tonemap"])

    grids: dict = {}
    if args.only in (None, "village.png"):
        village = [shot("village", [f"time.hour={hour}"], (w, h)) for hour in (10.0, 18.67, 22.0)]
        village.append(shot("village", ["time.hour=14", "vr.enabled=true"], (w, h)))
        grids["village.png"] = np.concatenate([np.concatenate(village[:2], axis=1),
                                               np.concatenate(village[2:], axis=1)], axis=0)
        if args.only is not None:
            return _save(grids, args.force)
    sky = [shot(scene, [f"time.hour={hour}"], (w, h)) for scene, hour, _ in SHOTS]
    grids |= {
        "sky.png": np.concatenate([np.concatenate(sky[:2], axis=1),
                                   np.concatenate(sky[2:], axis=1)], axis=0),
        "materials.png": np.concatenate([
            np.concatenate([shot("materials", [f"material={m}", f"noise={n}"], (w, w * 2 // 5))
                            for n in ("value", "gradient")],
                           axis=1) for m in ("wood", "marble", "granite")], axis=0),
    }
    planet = [
        shot("planet", ["planet.method=shadowed"], (w, h)),
        shot("planet", ["planet.method=hillaire", "planet.sun_elevation=3",
                        "planet.sun_azimuth=0"], (w, h)),
        shot("planet", ["planet.method=brute_force", "planet.sun_elevation=12",
                        "planet.sun_azimuth=20"], (w, h)),
        shot("planet", ["planet.method=hillaire", "planet.sun_elevation=20",
                        "planet.sun_azimuth=90"], (w, h),
             {"position": (0.0, 400000.0, 60.0), "pitch": -35.0}),
    ]
    grids["planet.png"] = np.concatenate([np.concatenate(planet[:2], axis=1),
                                          np.concatenate(planet[2:], axis=1)], axis=0)
    clouds = [shot("clouds", ["time.hour=10", f"clouds.preset={preset}"], (w, h))
              for preset in ("cumulus", "stratocumulus", "stratus")]
    clouds.append(shot("clouds", ["scene.model=b", "scene.sky=preetham"], (w, h)))
    grids["clouds.png"] = np.concatenate([np.concatenate(clouds[:2], axis=1),
                                          np.concatenate(clouds[2:], axis=1)], axis=0)
    ocean = [
        shot("ocean", ["ocean.wind=12", "time.hour=17"], (w, h)),
        shot("ocean", ["ocean.model=sine", "ocean.wind=12", "ocean.sine_amplitude=0.6",
                       "time.hour=12"], (w, h),
             {"position": (0.0, 6.0, 0.0), "yaw": 150.0, "pitch": -8.0}),
        shot("ocean", ["ocean.model=gerstner", "ocean.wind=12", "time.hour=12"], (w, h),
             {"position": (0.0, 6.0, 0.0), "yaw": 150.0, "pitch": -8.0}),
        shot("ocean", ["ocean.wind=8", "scene.clouds=b", "time.hour=12"], (w, h),
             {"position": (0.0, -3.0, 0.0), "yaw": 200.0, "pitch": 50.0}),
    ]
    grids["ocean.png"] = np.concatenate([np.concatenate(ocean[:2], axis=1),
                                         np.concatenate(ocean[2:], axis=1)], axis=0)
    return _save(grids, args.force)


def _save(grids: dict, force: bool) -> int:
    from PIL import Image

    for name, grid in grids.items():
        out = PROJECT_ROOT / "docs" / name
        if out.exists() and not force:
            print(f"{out} exists: pass --force to replace it", file=sys.stderr)
            continue
        Image.fromarray(grid).save(out)
        print(out)
    return 0

if __name__ == "__main__":
    sys.exit(main())
