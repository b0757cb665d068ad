"""The moon and star textures are cached like the bakes: in the process and on disk, a file that
is damaged or stale is rebuilt and never trusted, and what the cache returns is exactly what
the generator makes."""

from __future__ import annotations

import numpy as np
import pytest

from app.sim import textures
from app.sim.textures import (
    MAGIC,
    cached_texture,
    decode_texture,
    encode_texture,
    load_or_build,
    moon_texture,
    star_field,
    texture_path,
)

# small parameters keep these tests fast; the generators are the ones the sky uses
STARS = {"seed": 11, "width": 64, "height": 32, "count": 40}
MOON = {"size": 32, "seed": 3}


@pytest.mark.parametrize("kind, params, make", [("stars", STARS, star_field),
                                                 ("moon", MOON, moon_texture)])
def test_a_cached_texture_is_identical_to_a_fresh_build(tmp_path, kind, params, make):
    fresh = make(**params)
    built, status = load_or_build(kind, params, tmp_path)
    assert status == "miss" and texture_path(kind, params, tmp_path).is_file()
    read, status = load_or_build(kind, params, tmp_path)
    assert status == "hit"
    for arr in (built, read):
        assert arr.dtype == fresh.dtype == np.float32 and arr.shape == fresh.shape
        assert arr.tobytes() == fresh.tobytes()


def test_a_cached_texture_is_read_only(tmp_path):
    a = cached_texture("moon", directory=tmp_path, **MOON)
    b = cached_texture("moon", directory=tmp_path, **MOON)  # read back from the file
    assert not a.flags.writeable and not b.flags.writeable
    with pytest.raises(ValueError):
        a[0, 0, 0] = 1.0
    assert np.array_equal(a, moon_texture(**MOON)) and np.array_equal(b, a)


def test_no_folder_means_no_file(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    assert cached_texture("stars", None, **STARS).tobytes() == star_field(**STARS).tobytes()
    assert not list(tmp_path.iterdir())


def _damaged(blob: bytes) -> dict[str, bytes]:
    mid = len(blob) // 2
    return {
        "empty": b"",
        "truncated": blob[: len(blob) - 100],
        "flipped byte": blob[:mid] + bytes([blob[mid] ^ 0xFF]) + blob[mid + 1:],
        "foreign": b"P6\n" + blob[3:],
        "a bake file": b"NATBAKE\n" + blob[8:],
    }


@pytest.mark.parametrize("damage", list(_damaged(b"x" * 200)))
def test_a_damaged_file_is_rebuilt_and_rewritten(tmp_path, damage):
    path = texture_path("stars", STARS, tmp_path)
    load_or_build("stars", STARS, tmp_path)
    good = path.read_bytes()
    path.write_bytes(_damaged(good)[damage])
    arr, status = load_or_build("stars", STARS, tmp_path)
    assert status.startswith("rebuilt: "), status
    assert arr.tobytes() == star_field(**STARS).tobytes()
    assert path.read_bytes() == good, "the file was rewritten whole"
    assert not [p for p in tmp_path.iterdir() if p != path], "no temporary file left behind"


def test_a_stale_file_is_rebuilt(tmp_path, monkeypatch):
    path = texture_path("moon", MOON, tmp_path)
    load_or_build("moon", MOON, tmp_path)
    monkeypatch.setattr(textures, "TEXTURE_VERSION", textures.TEXTURE_VERSION + 1)
    arr, status = load_or_build("moon", MOON, tmp_path)
    assert status.startswith("rebuilt: stale"), status
    assert arr.tobytes() == moon_texture(**MOON).tobytes()
    assert load_or_build("moon", MOON, tmp_path)[1] == "hit"
    # a file that names other parameters than the ones asked for is stale, not used
    other = dict(MOON, seed=4)
    assert decode_texture(path.read_bytes(), "moon", other)[1].startswith("stale")


def test_a_file_with_a_wrong_payload_under_a_valid_checksum_is_refused():
    import hashlib

    blob = encode_texture("moon", MOON, moon_texture(**MOON))
    body = blob[:-32] + b"\0\0\0\0"  # a longer payload, re-signed
    arr, why = decode_texture(body + hashlib.sha256(body).digest(), "moon", MOON)
    assert arr is None and why.startswith("corrupt"), why
    assert blob.startswith(MAGIC)


def test_an_unwritable_cache_still_gives_the_texture(tmp_path):
    blocker = tmp_path / "file"
    blocker.write_text("not a folder")
    arr, status = load_or_build("stars", STARS, blocker / "cache")
    assert status != "hit" and arr.tobytes() == star_field(**STARS).tobytes()
