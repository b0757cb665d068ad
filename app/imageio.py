"""Image output: PNG (tone-mapped sRGB, :func:`app.colour.to_srgb8`) and EXR (linear,
pre-tone-map radiance).

Files are written atomically (a temporary file beside the target, then a rename) and an
existing file is never replaced unless ``force`` is given: the no-clobber case uses a hard
link, which fails if the name was taken in the meantime.
"""

from __future__ import annotations

import os
import re
import tempfile
from pathlib import Path

import numpy as np

from .colour import to_srgb8
from .errors import OutputExistsError, UsageError

IMAGE_SUFFIXES = (".png", ".exr")


# ---- paths ---------------------------------------------------------------------------------

def check_output_path(path: str | os.PathLike, force: bool = False,
                      suffixes=IMAGE_SUFFIXES) -> Path:
    """Validate an output path before any work is done: known suffix, writable folder, and
    no existing file unless ``force``."""
    p = Path(path).expanduser()
    if p.suffix.lower() not in suffixes:
        raise UsageError(f"output {str(p)!r} has an unsupported extension: "
                         f"allowed {', '.join(suffixes)}")
    parent = p.parent if str(p.parent) else Path(".")
    if not parent.is_dir():
        raise UsageError(f"output folder {str(parent)!r} does not exist: "
                         "allowed an existing, writable folder")
    if not _can_create_in(parent):
        raise UsageError(f"output folder {str(parent)!r} is not writable: "
                         "allowed an existing, writable folder")
    if p.is_dir():
        raise UsageError(f"output {str(p)!r} is a folder: "
                         f"allowed a file name ending in {', '.join(suffixes)}")
    if p.exists() and not force:
        raise OutputExistsError(f"refusing to overwrite {str(p)!r}: "
                                "pass --force or choose another name")
    return p


def _can_create_in(folder: Path) -> bool:
    """Whether a file can be created in ``folder``: ``os.access`` alone says yes to root on
    read-only or special file systems (``/proc``), so try it with a temporary file."""
    if not os.access(folder, os.W_OK):
        return False
    try:
        fd, name = tempfile.mkstemp(prefix=".natura-probe.", dir=folder)
    except OSError:
        return False
    os.close(fd)
    os.unlink(name)
    return True


def next_free_path(folder: str | os.PathLike, stem: str, suffix: str) -> Path:
    """``folder/stem-0001.suffix``, the first number not taken (never overwrites)."""
    folder = Path(folder)
    taken = set()
    pattern = re.compile(rf"^{re.escape(stem)}-(\d+){re.escape(suffix)}$")
    if folder.is_dir():
        for entry in folder.iterdir():
            m = pattern.match(entry.name)
            if m:
                taken.add(int(m.group(1)))
    n = max(taken, default=0) + 1
    return folder / f"{stem}-{n:04d}{suffix}"


def _atomic_commit(tmp: Path, path: Path, force: bool) -> None:
    try:
        if force:
            os.replace(tmp, path)
        else:
            try:
                os.link(tmp, path)  # fails if the name exists: no clobbering, even in a race
            except FileExistsError:
                raise OutputExistsError(f"refusing to overwrite {str(path)!r}: "
                                        "pass --force or choose another name") from None
            except OSError:  # file systems without hard links
                if path.exists():
                    raise OutputExistsError(f"refusing to overwrite {str(path)!r}: "
                                            "pass --force or choose another name") from None
                os.replace(tmp, path)
    finally:
        if tmp.exists():
            tmp.unlink()


def _temp_beside(path: Path) -> Path:
    fd, name = tempfile.mkstemp(prefix=f".{path.stem}.", suffix=path.suffix,
                                dir=path.parent if str(path.parent) else ".")
    os.close(fd)
    return Path(name)


def write_text_atomic(path: str | os.PathLike, text: str, force: bool = False) -> Path:
    path = Path(path)
    tmp = _temp_beside(path)
    tmp.write_text(text, encoding="utf-8")
    _atomic_commit(tmp, path, force)
    return path


# ---- writers and readers -------------------------------------------------------------------

def write_png(path: str | os.PathLike, rgb: np.ndarray, exposure: float = 1.0, mode: str = "aces",
              force: bool = False) -> Path:
    """Tone-map linear radiance ``(h, w, 3|4)`` and write an 8-bit sRGB PNG atomically."""
    from PIL import Image

    path = Path(path)
    pixels = to_srgb8(np.asarray(rgb)[..., :3], exposure, mode)
    tmp = _temp_beside(path)
    Image.fromarray(pixels, "RGB").save(tmp, format="PNG")
    _atomic_commit(tmp, path, force)
    return path


def write_exr(path: str | os.PathLike, rgb: np.ndarray, force: bool = False) -> Path:
    """Write linear radiance ``(h, w, 3|4)`` as a 32-bit float RGB OpenEXR file atomically."""
    import OpenEXR

    path = Path(path)
    pixels = np.ascontiguousarray(np.asarray(rgb, dtype=np.float32)[..., :3])
    header = {"compression": OpenEXR.ZIP_COMPRESSION, "type": OpenEXR.scanlineimage}
    tmp = _temp_beside(path)
    with OpenEXR.File(header, {"RGB": pixels}) as f:
        f.write(str(tmp))
    _atomic_commit(tmp, path, force)
    return path


def write_image(path: str | os.PathLike, rgb: np.ndarray, exposure: float = 1.0, mode: str = "aces",
                force: bool = False) -> Path:
    if Path(path).suffix.lower() == ".exr":
        return write_exr(path, rgb, force=force)
    return write_png(path, rgb, exposure, mode, force=force)


def read_png(path: str | os.PathLike) -> np.ndarray:
    from PIL import Image

    with Image.open(path) as im:
        return np.asarray(im.convert("RGB"))


def read_exr(path: str | os.PathLike) -> np.ndarray:
    import OpenEXR

    with OpenEXR.File(str(path)) as f:
        channels = f.channels()
        if "RGB" in channels:
            return np.asarray(channels["RGB"].pixels, dtype=np.float32)
        return np.stack([np.asarray(channels[c].pixels, dtype=np.float32) for c in "RGB"], axis=-1)
