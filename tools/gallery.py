"""Render every scene's views (resources/presets/views/SCENE/*.toml) into docs/gallery/:

    python tools/gallery.py [--scenes maritime,village] [--size 1280x720] [--out docs/gallery]

For each view, exactly as ``natura render SCENE --view NAME`` renders it: ``SCENE/NAME.jpg``
(JPEG at quality 92: forty 1280×720 PNGs would put ~60 MB in the repository), and its look's
figures (``app.teach.look.figures``, computed on the 8-bit image before compression) in
``SCENE/figures.json``; per scene a contact sheet ``SCENE.jpg`` (the views side by side, each
with its title); and ``README.md``, the index the project README links to, with every view's
title, lesson, command line and figures. Files of the gallery are replaced; nothing else is
written.
"""

from __future__ import annotations

import argparse
import io
import json
import sys
import time
from pathlib import Path

import numpy as np

from app import PROJECT_ROOT
from app.imageio import write_bytes_atomic, write_text_atomic
from app.runtime import parse_size
from app.scenes import SCENES
from app.scenes.views import views_of
from app.teach.look import render_view

THUMB = (640, 360)
COLUMNS = 2


def _jpeg(pixels: np.ndarray, quality: int = 92) -> bytes:
    from PIL import Image

    buf = io.BytesIO()
    Image.fromarray(pixels, "RGB").save(buf, format="JPEG", quality=quality, optimize=True)
    return buf.getvalue()


def contact_sheet(images: list[np.ndarray], titles: list[str]) -> np.ndarray:
    """The views as thumbnails in a grid, each titled underneath."""
    from matplotlib import font_manager
    from PIL import Image, ImageDraw, ImageFont

    font = ImageFont.truetype(font_manager.findfont("DejaVu Sans"), 18)
    w, h = THUMB
    label = 30
    rows = (len(images) + COLUMNS - 1) // COLUMNS
    sheet = Image.new("RGB", (w * COLUMNS, (h + label) * rows), (24, 24, 28))
    draw = ImageDraw.Draw(sheet)
    for i, (image, title) in enumerate(zip(images, titles)):
        x, y = (i % COLUMNS) * w, (i // COLUMNS) * (h + label)
        sheet.paste(Image.fromarray(image).resize(THUMB, Image.LANCZOS), (x, y))
        draw.text((x + 8, y + h + 5), title, fill=(230, 230, 230), font=font)
    return np.asarray(sheet)


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--scenes", default=",".join(SCENES))
    ap.add_argument("--size", default="1280x720")
    ap.add_argument("--out", default=str(PROJECT_ROOT / "docs" / "gallery"))
    args = ap.parse_args(argv)
    size = parse_size(args.size)
    out = Path(args.out)
    scenes = [s.strip() for s in args.scenes.split(",") if s.strip()]
    index_path = out / "index.json"
    index = json.loads(index_path.read_text()) if index_path.is_file() else {}
    for scene in scenes:
        views = views_of(scene)
        folder = out / scene
        folder.mkdir(parents=True, exist_ok=True)
        images, entries = [], []
        for view in views:
            t0 = time.perf_counter()
            image, figures = render_view(view, size)
            write_bytes_atomic(folder / f"{view.name}.jpg", _jpeg(image), force=True)
            images.append(image)
            entries.append({"view": view.name, "title": view.title, "lesson": view.lesson,
                            "command": f"natura render {scene} --view {view.name}",
                            "size": list(size), "figures": figures})
            print(f"{scene}/{view.name}: {time.perf_counter() - t0:.1f} s  {figures}",
                  flush=True)
        write_text_atomic(folder / "figures.json", json.dumps(entries, indent=1) + "\n",
                          force=True)
        if images:
            write_bytes_atomic(out / f"{scene}.jpg",
                               _jpeg(contact_sheet(images, [v.title for v in views]), 88),
                               force=True)
        index[scene] = entries
    write_text_atomic(index_path, json.dumps(index, indent=1) + "\n", force=True)
    write_text_atomic(out / "README.md", _markdown(index), force=True)
    return 0


def _markdown(index: dict) -> str:
    lines = ["# Gallery", "",
             "Every scene's views, rendered at 1280×720 by `python tools/gallery.py` exactly as "
             "`natura render SCENE --view NAME` renders them (Mesa llvmpipe). Beside each: the "
             "look's figures, computed from the 8-bit image (`app/teach/look.py`): luma spread "
             "(p95 − p5 of 0–255), distinct luma levels, the share of pixels within 2/255 of the "
             "commonest luma, mean saturation, clipped pixels, and sky against sea or land at "
             "the horizon.", ""]
    for scene in [s for s in SCENES if s in index]:
        lines += [f"## {scene}", "", f"![{scene}]({scene}.jpg)", ""]
        lines += ["| view | what it shows | spread | levels | mode | sat. | clipped | horizon |",
                  "|---|---|---|---|---|---|---|---|"]
        for e in index[scene]:
            f = e["figures"]
            hz = "—" if f["horizon_contrast"] is None else f"{f['horizon_contrast']:+.3f}"
            lines.append(f"| [`{e['view']}`]({scene}/{e['view']}.jpg) | **{e['title']}** — "
                         f"{e['lesson']} (`{e['command']}`) | {f['luma_spread']:.0f} | "
                         f"{f['luma_levels']} | {f['mode_fraction']:.0%} | "
                         f"{f['saturation']:.2f} | {f['clipped']:.1%} | {hz} |")
        lines.append("")
    return "\n".join(lines)


if __name__ == "__main__":
    sys.exit(main())
