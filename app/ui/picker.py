"""The scene picker: what ``natura`` opens when no scene is named — a window of the gallery's
thumbnails, one tile per scene with its name and title. A click on a tile (or Enter, for the
highlighted one; the arrow keys move it) closes the picker and returns that scene's name; Esc
or closing the window returns None.

The thumbnails are each scene's first gallery view (a JPEG in the scene's folder of
``docs/gallery/``, listed in ``docs/gallery/index.json``), scaled down when the picker opens; a
scene without one shows its name on a plain tile. The layout is a pure function
(:func:`tile_rects`), which the window tests use to click a tile the way a person does.
"""

from __future__ import annotations

import json
from dataclasses import dataclass
from pathlib import Path

from .. import PROJECT_ROOT
from ..scenes import SCENES

GALLERY = PROJECT_ROOT / "docs" / "gallery"
TITLE = "Natura — choose a scene"
#: a tile: the thumbnail's size in pixels and the text lines under it
THUMB = (256, 144)
TEXT_H = 46
GAP = 12
MARGIN = 16
HEADER_H = 40


@dataclass(frozen=True)
class Tile:
    scene: str
    title: str
    image: Path | None


def tiles(default: str) -> list[Tile]:
    """One tile per registered scene, ``default`` first, then the registry's order."""
    try:
        index = json.loads((GALLERY / "index.json").read_text(encoding="utf-8"))
    except (OSError, ValueError):
        index = {}
    names = [default] + [n for n in SCENES if n != default]
    out = []
    for name in names:
        cls = SCENES[name]
        views = index.get(name) or []
        image = GALLERY / name / f"{views[0]['view']}.jpg" if views else None
        out.append(Tile(name, cls.title, image if image is not None and image.is_file() else None))
    return out


def _scale(size: tuple[int, int], count: int, cols: int) -> float:
    rows = -(-count // cols)
    across = (size[0] - 2 * MARGIN - (cols - 1) * GAP) / (cols * THUMB[0])
    down = (size[1] - HEADER_H - MARGIN - rows * (TEXT_H + GAP)) / (rows * THUMB[1])
    return min(1.0, across, down)


def columns(size: tuple[int, int], count: int) -> int:
    """Tiles per row in a window of ``size`` pixels: the count that shows every tile at once
    with the largest thumbnails (at most full size; the fewest columns among equals)."""
    best = max(_scale(size, count, c) for c in range(1, count + 1))
    return next(c for c in range(1, count + 1) if _scale(size, count, c) >= best - 1e-9)


def tile_rects(size: tuple[int, int], count: int) -> list[tuple[float, float, float, float]]:
    """Each tile's thumbnail (x, y, w, h) in window pixels (y down), row by row, scaled so
    that every tile fits the window (a thumbnail is at least 32 pixels wide)."""
    size = (int(size[0]), int(size[1]))
    cols = columns(size, count)
    scale = max(_scale(size, count, cols), 32.0 / THUMB[0])
    tw, th = THUMB[0] * scale, THUMB[1] * scale
    out = []
    for i in range(count):
        r, c = divmod(i, cols)
        out.append((MARGIN + c * (tw + GAP), HEADER_H + r * (th + TEXT_H + GAP), tw, th))
    return out


def _thumbnail(path: Path | None):
    """(h, w, 4) uint8 RGBA pixels of ``path`` scaled to fit THUMB (letterboxed), or None."""
    if path is None:
        return None
    import numpy as np
    from PIL import Image

    try:
        with Image.open(path) as im:
            im = im.convert("RGB")
            im.thumbnail(THUMB, Image.Resampling.LANCZOS)
            canvas = Image.new("RGB", THUMB, (20, 20, 24))
            canvas.paste(im, ((THUMB[0] - im.width) // 2, (THUMB[1] - im.height) // 2))
            return np.dstack([np.asarray(canvas), np.full(THUMB[::-1], 255, np.uint8)])
    except OSError:
        return None


def pick_scene(default: str, size=(1280, 720), frames: int | None = None) -> str | None:
    """Open the picker; the scene chosen, or None (Esc, the window closed, or ``frames``
    frames drawn without a choice)."""
    from imgui_bundle import imgui

    from .imgui_renderer import ImguiRenderer
    from .window import _create_window, _load_font

    wnd = _create_window(size, TITLE)
    wnd.exit_key = None
    entries = tiles(default)
    imgui.create_context()
    imgui.get_io().set_ini_filename("")
    _load_font(imgui)  # the window's own fonts: the titles' dashes and Greek letters
    ui = ImguiRenderer(wnd)
    keys = wnd.keys
    state = {"chosen": None, "cancel": False, "focus": 0}

    def on_key(key, action, modifiers):
        ui.key_event(key, action, modifiers)
        if action != keys.ACTION_PRESS:
            return
        cols = columns(wnd.size, len(entries))
        moves = {keys.RIGHT: 1, keys.LEFT: -1, keys.DOWN: cols, keys.UP: -cols}
        if key == keys.ESCAPE:
            state["cancel"] = True
        elif key in (keys.ENTER, getattr(keys, "NUMPAD_ENTER", keys.ENTER)):
            state["chosen"] = entries[state["focus"]].scene
        elif key in moves:
            state["focus"] = int(min(max(state["focus"] + moves[key], 0), len(entries) - 1))

    wnd.key_event_func = on_key
    wnd.mouse_position_event_func = ui.mouse_position_event
    wnd.mouse_drag_event_func = ui.mouse_drag_event
    wnd.mouse_press_event_func = ui.mouse_press_event
    wnd.mouse_release_event_func = ui.mouse_release_event
    wnd.mouse_scroll_event_func = ui.mouse_scroll_event
    wnd.resize_func = ui.resize
    textures = []
    try:
        for entry in entries:
            pixels = _thumbnail(entry.image)
            tex = None
            if pixels is not None:
                tex = wnd.ctx.texture(THUMB, 4, pixels[::-1].tobytes())
                ui.register_texture(tex)
            textures.append(tex)
        n = 0
        while not wnd.is_closing and state["chosen"] is None and not state["cancel"]:
            if frames is not None and n >= frames:
                break
            wnd.use()
            wnd.clear(0.08, 0.08, 0.09, 1.0)
            imgui.get_io().delta_time = 1.0 / 60.0
            imgui.new_frame()
            _draw(imgui, wnd.size, entries, textures, state)
            imgui.render()
            ui.render(imgui.get_draw_data())
            wnd.swap_buffers()
            n += 1
    finally:
        for tex in textures:
            if tex is not None:
                ui.remove_texture(tex)
                tex.release()
        ui.shutdown()
        imgui.destroy_context()
        wnd.close()
        wnd.destroy()
    return state["chosen"]


def _draw(imgui, size, entries, textures, state) -> None:
    w, h = size
    imgui.set_next_window_pos((0, 0))
    imgui.set_next_window_size((w, h))
    flags = (imgui.WindowFlags_.no_decoration | imgui.WindowFlags_.no_move
             | imgui.WindowFlags_.no_saved_settings)
    imgui.begin("scenes", flags=flags)
    imgui.set_cursor_pos((MARGIN, 12))
    imgui.text("Choose a scene: click it, or Enter for the highlighted one (arrows move, "
               "Esc quits). Each opens in the window with its panel.")
    rects = tile_rects((w, h), len(entries))
    for i, (entry, tex, (x, y, tw, th)) in enumerate(zip(entries, textures, rects)):
        imgui.set_cursor_pos((x, y))
        imgui.push_id(entry.scene)
        if tex is not None:
            clicked = imgui.image_button(f"##{entry.scene}", imgui.ImTextureRef(tex.glo),
                                         (tw, th), (0.0, 1.0), (1.0, 0.0))
        else:
            clicked = imgui.button(entry.title or entry.scene, (tw, th))
        if clicked:
            state["chosen"] = entry.scene
        if imgui.is_item_hovered():
            state["focus"] = i
        if i == state["focus"]:
            lo, hi = imgui.get_item_rect_min(), imgui.get_item_rect_max()
            gold = imgui.get_color_u32((1.0, 0.8, 0.3, 1.0))
            imgui.get_window_draw_list().add_rect(lo, hi, gold, rounding=0.0, thickness=3.0)
        imgui.set_cursor_pos((x, y + th + 3))
        imgui.text(entry.scene)
        imgui.set_cursor_pos((x, y + th + 3 + imgui.get_text_line_height()))
        imgui.push_text_wrap_pos(x + tw)
        imgui.text_disabled(entry.title)
        imgui.pop_text_wrap_pos()
        imgui.pop_id()
    imgui.end()
