"""Pinned renders: every scene's defaults (``--view none``) and every view, rendered headless at
160x90 as linear float32 radiance, exactly as ``natura render SCENE --view NAME --size 160x90
--out FILE.exr`` renders them. A refactor that must not change a picture is checked with it:

    python tools/pinned_renders.py --out /tmp/pins-before      # before the change
    python tools/pinned_renders.py --compare /tmp/pins-before  # after: exit 1 on any difference

``--compare`` renders again and compares each image with the stored one bit for bit (NaN equal to
NaN), printing one line per picture that changed (its largest difference, the share of pixels).
"""

from __future__ import annotations

import argparse
import os
import sys
import tempfile
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

SIZE = (160, 90)


def pinned() -> list[tuple[str, str | None]]:
    """(scene, view or None for the defaults) of every pinned render."""
    from app.scenes import SCENES
    from app.scenes.views import views_of

    return [(scene, None) for scene in SCENES] + [
        (scene, v.name) for scene in SCENES for v in views_of(scene)]


def render(scene: str, view: str | None, ctx) -> np.ndarray:
    from app.runtime import open_session, placed_camera, render_frames, scene_params
    from app.scenes.views import get_view

    v = get_view(scene, view) if view is not None else None
    params = scene_params(scene, view=v)
    camera = placed_camera(scene, params, v)
    session = open_session(scene, params, ctx=ctx, camera=camera)
    try:
        frames = render_frames(session, SIZE, warmup=(v.frames - 1) if v is not None else 0)
        try:
            return np.asarray(next(frames)[..., :3], dtype=np.float32)
        finally:
            frames.close()
    finally:
        session.release()


def name(scene: str, view: str | None) -> str:
    return f"{scene}--{view or 'defaults'}.npy"


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    group = ap.add_mutually_exclusive_group(required=True)
    group.add_argument("--out", help="a new folder to store the renders in")
    group.add_argument("--compare", help="a folder --out wrote: compare with it")
    args = ap.parse_args(argv)
    from app.gpu.context import create_headless_context

    ctx = create_headless_context()
    folder = Path(args.out or args.compare)
    if args.out is not None:
        if folder.exists():
            print(f"pinned_renders: --out {folder} exists: allowed a new folder", file=sys.stderr)
            return 2
        tmp = Path(tempfile.mkdtemp(prefix=".pins-", dir=folder.parent))
        try:
            for scene, view in pinned():
                np.save(tmp / name(scene, view), render(scene, view, ctx))
            os.replace(tmp, folder)
        finally:
            if tmp.exists():
                for f in tmp.iterdir():
                    f.unlink()
                tmp.rmdir()
        print(f"{len(pinned())} renders → {folder}")
        return 0
    changed = 0
    for scene, view in pinned():
        path = folder / name(scene, view)
        if not path.is_file():
            print(f"{scene} {view or '(defaults)'}: not in {folder}")
            changed += 1
            continue
        old, new = np.load(path), render(scene, view, ctx)
        if old.shape != new.shape or not np.array_equal(old, new, equal_nan=True):
            diff = np.abs(np.nan_to_num(old) - np.nan_to_num(new)) if old.shape == new.shape \
                else np.array([np.inf])
            print(f"{scene} {view or '(defaults)'}: changed, largest difference "
                  f"{float(diff.max()):.3g}, {100.0 * float((diff > 0).mean()):.2f} % of values")
            changed += 1
    print(f"{len(pinned()) - changed} of {len(pinned())} renders bit-identical")
    return 1 if changed else 0


if __name__ == "__main__":
    sys.exit(main())
