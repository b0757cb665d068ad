"""Image output: PNG (tone-mapped sRGB, :func:`app.colour.to_srgb8`) and EXR (linear,
pre-tone-map radiance).

Files are written atomically (a temporary ``.natura-XXXXXXXX.tmp`` beside the target, then a
rename) with the permissions the umask gives a new file, and an existing file is never replaced
unless ``force`` is given: the no-clobber case uses a hard link, which fails if the name was
taken in the meantime. A temporary file is removed on every error, on Ctrl-C and SIGTERM (the
CLI turns SIGTERM into an exception) and at exit; one left by SIGKILL is removed by a later
write in the same folder once it is an hour old.
"""

from __future__ import annotations

import atexit
import contextlib
import errno
import os
import re
import secrets
import shutil
import signal
import stat
import time
from pathlib import Path
from typing import Iterator

import numpy as np

from .colour import to_srgb8
from .errors import NaturaError, OutputExistsError, UsageError, quote, quote_path

IMAGE_SUFFIXES = (".png", ".exr")
#: temporary files are ``.natura-XXXXXXXX.tmp`` beside their target: short (a 250-byte target
#: name still fits), and recognisable (stale ones, left by a SIGKILL, are removed later)
TEMP_PREFIX, TEMP_SUFFIX = ".natura-", ".tmp"
#: a temporary file older than this (seconds) is a leftover of a killed run
STALE_AFTER = 3600.0
NAME_MAX = 255
_FOLDER_ALLOWED = "allowed an existing, writable folder"


class OutputError(UsageError):
    """An output that could not be written (full disk, read-only file system...): one line
    naming the file; the temporary file is removed. ``path``, ``why`` and ``allowed`` are its
    parts, for a caller that says more (the frames of a sequence kept before it)."""

    def __init__(self, message: str, path: Path | None = None, why: str = "",
                 allowed: str = ""):
        super().__init__(message)
        self.path, self.why, self.allowed = path, why, allowed


_UMASK: int | None = None


def file_mode() -> int:
    """``0o666 & ~umask``: the mode a plain ``open()`` would give a new file (``mkstemp``
    makes 0600). The umask is read once (setting it is the only way to read it)."""
    global _UMASK
    if _UMASK is None:
        _UMASK = os.umask(0o022)
        os.umask(_UMASK)
    return 0o666 & ~_UMASK


#: temporary files (and folders) being written now: removed on any error, and at exit
_LIVE: set[Path] = set()
#: the signals that end a run through an exception (Ctrl-C, and SIGTERM in the CLI)
_ENDING = (signal.SIGINT, signal.SIGTERM)


@contextlib.contextmanager
def signals_deferred() -> Iterator[None]:
    """Hold Ctrl-C and SIGTERM until the block ends: between creating a temporary file and
    registering it (or removing it) an interrupt would leave it behind. Outside the main
    thread, or without ``pthread_sigmask``, the block runs as it is."""
    try:
        old = signal.pthread_sigmask(signal.SIG_BLOCK, _ENDING)
    except (AttributeError, ValueError, OSError):
        old = None
    try:
        yield
    finally:
        if old is not None:
            signal.pthread_sigmask(signal.SIG_SETMASK, old)


def _remove(p: Path) -> None:
    with contextlib.suppress(OSError):
        if p.is_dir() and not p.is_symlink():
            shutil.rmtree(p, ignore_errors=True)
        else:
            p.unlink()
    _LIVE.discard(p)


@atexit.register
def remove_live_temps() -> None:
    """Remove every temporary file still registered (an interrupted write)."""
    for p in list(_LIVE):
        _remove(p)


def _remove_stale_temps(folder: Path) -> None:
    """Remove ``.natura-*.tmp`` files in ``folder`` older than :data:`STALE_AFTER` (left by a
    run that was killed with SIGKILL, where nothing can clean up)."""
    now = time.time()
    with contextlib.suppress(OSError):
        for entry in os.scandir(folder):
            if not (entry.name.startswith(TEMP_PREFIX) and entry.name.endswith(TEMP_SUFFIX)):
                continue
            with contextlib.suppress(OSError):
                st = entry.stat(follow_symlinks=False)
                if stat.S_ISREG(st.st_mode) and now - st.st_mtime > STALE_AFTER:
                    os.unlink(entry.path)


def temp_name_in(folder: Path) -> Path:
    """A fresh, unused temporary name in ``folder`` (not created)."""
    return folder / f"{TEMP_PREFIX}{secrets.token_hex(4)}{TEMP_SUFFIX}"


@contextlib.contextmanager
def temp_beside(path: Path) -> Iterator[Path]:
    """A temporary file beside ``path`` with the umask's permissions, registered while it
    lives; removed when the block fails (any exception, Ctrl-C, SIGTERM) or did not use it."""
    folder = path.parent
    _remove_stale_temps(folder)
    # The name is registered before the file exists: a Ctrl-C already caught by Python's
    # handler is raised between two bytecodes even while the signals are blocked, and one
    # raised right after the file was created must still find it registered (the CLI removes
    # every registered temporary file on its way out).
    with signals_deferred():
        for _ in range(100):
            tmp = temp_name_in(folder)
            _LIVE.add(tmp)
            try:
                fd = os.open(tmp, os.O_WRONLY | os.O_CREAT | os.O_EXCL, 0o600)
                break
            except FileExistsError:
                _LIVE.discard(tmp)
            except OSError as exc:
                _LIVE.discard(tmp)
                raise _write_error(path, exc) from None
        else:
            raise _write_error(path, FileExistsError(errno.EEXIST, "no free temporary name"))
    try:
        os.fchmod(fd, file_mode())
        os.close(fd)
        yield tmp
    finally:
        _remove(tmp)  # after a commit it is gone already


#: the system errors an encoder (OpenEXR, Pillow) may only name in its message's text
_TEXT_ERRNOS = (errno.ENOSPC, errno.EDQUOT, errno.EFBIG, errno.EROFS, errno.EACCES, errno.EIO)


def _why(exc: BaseException) -> tuple[int | None, str]:
    """(errno, a short reason) of a writer's failure. An encoder that reports a system error
    in its message's text (OpenEXR: ``Failed to write pixel data to image file "<its temporary
    file>". No space left on device.``) is read for it; the paths it quotes are dropped (the
    message names the output, not its temporary file)."""
    if isinstance(exc, OSError) and exc.errno:
        return exc.errno, os.strerror(exc.errno)
    text = str(exc)
    for code in _TEXT_ERRNOS:
        if os.strerror(code) in text:
            return code, os.strerror(code)
    text = " ".join(re.sub(r'"[^"]*"|\'[^\']*\'', "", text).split())
    why = f"{type(exc).__name__}: {text}" if text else type(exc).__name__
    return None, why if len(why) <= 60 else why[:57] + "..."


def _write_error(path: Path, exc: BaseException) -> OutputError:
    code, why = _why(exc)
    if code in (errno.ENOSPC, errno.EDQUOT, errno.EFBIG):
        allowed = "allowed a folder on a disk with free space"
    else:
        allowed = "allowed a writable folder with free space"
    return OutputError(f"cannot write {quote_path(path)} ({why}): {allowed}; "
                       "nothing was left behind", path, why, allowed)


@contextlib.contextmanager
def writing(path: Path) -> Iterator[None]:
    """Turn the failures of a writer (OSError, an encoder's RuntimeError) into one
    :class:`OutputError` naming ``path``; user errors pass through."""
    try:
        yield
    except NaturaError:
        raise
    except (OSError, RuntimeError, ValueError, MemoryError) as exc:
        raise _write_error(path, exc) from None


def expand(path: str | os.PathLike, what: str = "output") -> Path:
    """``Path(path).expanduser()``, or one line when it names an unknown user's home."""
    text = os.fspath(path)
    if isinstance(text, bytes):
        text = os.fsdecode(text)
    if not text.strip():
        raise UsageError(f"{what} name is empty: allowed a file name")
    if "\0" in text:
        raise UsageError(f"{what} {quote(text)} holds a NUL character: allowed a file name")
    try:
        return Path(text).expanduser()
    except RuntimeError:
        raise UsageError(f"{what} {quote(text)} names an unknown user's home folder: "
                         "allowed ~/..., ~USER/... for an existing user, or a plain path"
                         ) from None


def name_max(folder: Path) -> int:
    try:
        return int(os.pathconf(folder, "PC_NAME_MAX"))
    except (OSError, ValueError, AttributeError):
        return NAME_MAX


def check_output_path(path: str | os.PathLike, force: bool = False,
                      suffixes=IMAGE_SUFFIXES, probe_folder: bool = True) -> Path:
    """Validate an output path before any work is done: known suffix, a name that fits, a
    writable folder, and no existing file unless ``force`` (never something that is not a
    regular file, even with ``force``). ``probe_folder=False`` skips the writability probe (a
    file created and removed) for names in a folder a previous check just probed."""
    p = expand(path)
    shown = quote(str(p))
    text = os.fsdecode(os.fspath(path))
    if text.endswith(("/", os.sep, os.altsep or "/")) or text.endswith(("/.", "/..")):
        raise UsageError(f"output {quote(text)} ends in a folder separator (a folder's path): "
                         f"allowed a file name ending in {', '.join(suffixes)}")
    if p.suffix.lower() not in suffixes or p.name == p.suffix:
        raise UsageError(f"output {shown} has an unsupported extension: "
                         f"allowed {', '.join(suffixes)}")
    parent = p.parent
    try:
        parent_is_dir = parent.is_dir()
        exists = os.path.lexists(p)
        st = p.lstat() if exists else None
    except OSError as exc:  # a name too long for the system, a loop of links...
        raise UsageError(f"output {shown} cannot be used ({os.strerror(exc.errno or 0)}): "
                         "allowed a plain file name in an existing folder") from None
    if not parent_is_dir:
        what = "is not a folder" if os.path.lexists(parent) else "does not exist"
        raise UsageError(f"output folder {quote(str(parent))} {what}: {_FOLDER_ALLOWED}")
    limit = name_max(parent)
    if len(os.fsencode(p.name)) > limit:
        raise UsageError(f"output file name {quote(p.name)} is {len(os.fsencode(p.name))} "
                         f"bytes: allowed at most {limit}")
    if st is not None and stat.S_ISDIR(p.stat().st_mode if stat.S_ISLNK(st.st_mode)
                                        and p.exists() else st.st_mode):
        raise UsageError(f"output {shown} is a folder: "
                         f"allowed a file name ending in {', '.join(suffixes)}")
    if st is not None and not (stat.S_ISREG(st.st_mode) or stat.S_ISLNK(st.st_mode)):
        raise UsageError(f"output {shown} exists and is not a regular file (a pipe, socket or "
                         "device): allowed a new name, or an existing file with --force")
    if probe_folder and not _can_create_in(parent):
        raise UsageError(f"output folder {quote(str(parent))} is not writable: "
                         f"{_FOLDER_ALLOWED}")
    if st is not None and not force:
        raise refuse_overwrite(p)
    return p


def check_new_folder(path: Path, shown: str, allowed: str, option: str = "") -> Path:
    """Check that a new folder ``path`` can be made: its parent is a writable folder and its
    name fits. ``option`` (e.g. ``"--out "``) opens the messages. Returns the parent."""
    parent = path.parent
    if not parent.is_dir():
        what = "is not a folder" if os.path.lexists(parent) else "does not exist"
        raise UsageError(f"the folder {quote(str(parent))} of {option}{shown} {what}: {allowed}")
    if len(os.fsencode(path.name)) > name_max(parent):
        raise UsageError(f"{option}folder name {quote(path.name)} is "
                         f"{len(os.fsencode(path.name))} bytes: allowed at most "
                         f"{name_max(parent)}")
    if not _can_create_in(parent):
        raise UsageError(f"the folder {quote(str(parent))} is not writable: {allowed}")
    return parent


def refuse_overwrite(p: Path) -> OutputExistsError:
    return OutputExistsError(f"refusing to overwrite {quote(str(p))}: allowed with --force, "
                             "or choose another name")


def _can_create_in(folder: Path) -> bool:
    """Whether a file can be created in ``folder``: ``os.access`` alone says yes to root on
    read-only or special file systems (``/proc``), so try it with a temporary file."""
    if not os.access(folder, os.W_OK):
        return False
    with signals_deferred():  # the probe is created and removed as one step
        probe = temp_name_in(folder)
        _LIVE.add(probe)  # registered first, as in temp_beside
        try:
            fd = os.open(probe, os.O_WRONLY | os.O_CREAT | os.O_EXCL, 0o600)
        except OSError:
            _LIVE.discard(probe)
            return False
        os.close(fd)
        _remove(probe)
    return True


def next_free_path(folder: str | os.PathLike, stem: str, suffix: str,
                   also: tuple[str, ...] = ()) -> Path:
    """``folder/stem-0001.suffix``, the first number above those taken (never overwrites);
    with ``also`` (e.g. ``(".png",)`` for a report's chart), those names must be free too."""
    folder = Path(folder)
    taken = set()
    suffixes = "|".join(re.escape(s) for s in (suffix, *also))
    pattern = re.compile(rf"^{re.escape(stem)}-(\d+)(?:{suffixes})$")
    if folder.is_dir():
        for entry in folder.iterdir():
            m = pattern.match(entry.name)
            if m:
                taken.add(int(m.group(1)))
    n = max(taken, default=0) + 1
    return folder / f"{stem}-{n:04d}{suffix}"


def _atomic_commit(tmp: Path, path: Path, force: bool) -> None:
    """Give the finished ``tmp`` its name: replace with ``force``, else a hard link, which
    fails if the name was taken in the meantime (no clobbering, even in a race)."""
    try:
        if force:
            os.replace(tmp, path)
            return
        try:
            os.link(tmp, path)
        except FileExistsError:
            raise refuse_overwrite(path) from None
        except OSError as exc:
            if exc.errno not in (errno.EPERM, errno.EOPNOTSUPP, errno.EXDEV, errno.EMLINK,
                                 errno.ENOSYS):
                raise _write_error(path, exc) from None
            if os.path.lexists(path):  # file systems without hard links
                raise refuse_overwrite(path) from None
            os.replace(tmp, path)
    except OSError as exc:
        raise _write_error(path, exc) from None
    finally:
        _remove(tmp)


def write_bytes_atomic(path: str | os.PathLike, data: bytes, force: bool = False) -> Path:
    path = Path(path)
    with temp_beside(path) as tmp, writing(path):
        with open(tmp, "wb") as f:
            f.write(data)
            f.flush()
            os.fsync(f.fileno())
        _atomic_commit(tmp, path, force)
    return path


def write_text_atomic(path: str | os.PathLike, text: str, force: bool = False) -> Path:
    return write_bytes_atomic(path, text.encode("utf-8"), force=force)


def save_figure(fig, path: str | os.PathLike, force: bool = False, dpi: int = 90) -> Path:
    """``fig.savefig`` atomically: to a temporary file beside ``path``, then the same
    no-clobber commit as images (a chart is never overwritten without ``force``)."""
    path = Path(path)
    fmt = path.suffix.lstrip(".").lower() or "png"
    with temp_beside(path) as tmp, writing(path):
        fig.savefig(tmp, format=fmt, dpi=dpi)
        _atomic_commit(tmp, path, force)
    return path


def write_png(path: str | os.PathLike, rgb: np.ndarray, exposure: float = 1.0, mode: str = "aces",
              force: bool = False) -> Path:
    """Tone-map linear radiance ``(h, w, 3|4)`` and write an 8-bit sRGB PNG atomically."""
    from PIL import Image

    path = Path(path)
    pixels = to_srgb8(np.asarray(rgb)[..., :3], exposure, mode)
    with temp_beside(path) as tmp, writing(path):
        Image.fromarray(pixels, "RGB").save(tmp, format="PNG")
        _atomic_commit(tmp, path, force)
    return path


def write_exr(path: str | os.PathLike, rgb: np.ndarray, force: bool = False) -> Path:
    """Write linear radiance ``(h, w, 3|4)`` as a 32-bit float RGB OpenEXR file atomically."""
    import OpenEXR

    path = Path(path)
    pixels = np.ascontiguousarray(np.asarray(rgb, dtype=np.float32)[..., :3])
    header = {"compression": OpenEXR.ZIP_COMPRESSION, "type": OpenEXR.scanlineimage}
    with temp_beside(path) as tmp, writing(path):
        with OpenEXR.File(header, {"RGB": pixels}) as f:
            f.write(str(tmp))
        _atomic_commit(tmp, path, force)
    return path


def write_image(path: str | os.PathLike, rgb: np.ndarray, exposure: float = 1.0, mode: str = "aces",
                force: bool = False) -> Path:
    if Path(path).suffix.lower() == ".exr":
        return write_exr(path, rgb, force=force)
    return write_png(path, rgb, exposure, mode, force=force)

