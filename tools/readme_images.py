"""Regenerate docs/sky.png, the README's screenshot: the `sky` scene at four hours and the
`probe` scene, rendered headless exactly as `natura render` does.

    python tools/readme_images.py [--force]
"""

from __future__ import annotations

import argparse
import sys

import numpy as np

from app import PROJECT_ROOT
from app.imageio import to_srgb8
from app.runtime import open_session, render_frames, scene_params

SHOTS = [("sky", 6.3, "sunrise"), ("sky", 12.0, "noon"), ("sky", 18.5, "sunset"), ("sky", 0.0, "midnight")]


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("--force", action="store_true", help="replace docs/sky.png")
    ap.add_argument("--size", default="480x270")
    args = ap.parse_args(argv)
    w, h = (int(v) for v in args.size.split("x"))
    tiles = []
    for scene, hour, _ in SHOTS:
        params = scene_params(scene, sets=[f"time.hour={hour}"])
        session = open_session(scene, params)
        image = next(render_frames(session, (w, h)))
        tiles.append(to_srgb8(image[..., :3], params["output.exposure"], params["output.tonemap"]))
        session.release()
    grid = np.concatenate([np.concatenate(tiles[:2], axis=1), np.concatenate(tiles[2:], axis=1)], axis=0)
    from PIL import Image

    out = PROJECT_ROOT / "docs" / "sky.png"
    if out.exists() and not args.force:
        print(f"{out} exists: pass --force to replace it", file=sys.stderr)
        return 2
    Image.fromarray(grid).save(out)
    print(out)
    return 0


if __name__ == "__main__":
    sys.exit(main())
