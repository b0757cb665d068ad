"""The A/B comparison on a live session, as the window calls it (app/teach/compare.py): the
session's parameters, camera and time are the base, and the session is left as it was."""

from __future__ import annotations

import numpy as np

from app.runtime import render_frames
from app.teach.compare import compare, compose


def test_compare_on_a_live_session_leaves_it_as_it_was(render):
    size = (64, 36)
    image, session = render("sky", size, sets=("time.hour=17",))
    session.scene.camera.set(yaw=250.0, pitch=5.0)
    (before,) = list(render_frames(session, size))
    values = dict(session.params.values())
    cmp = compare(None, {"sky.sun_size": 0.3}, (), session=session, size=size, rounds=1)
    assert cmp.scene == "sky" and cmp.a.label == "sky.sun_size=0.3"
    assert cmp.b.label == "base (no changes)"
    # B is the session's own view: its parameters, camera and time of day
    np.testing.assert_allclose(cmp.b.image, before[..., :3], rtol=1e-5, atol=1e-6)
    assert np.abs(cmp.diff).max() > 0  # a bigger sun in A
    assert "--set time.hour=17" in cmp.command and "--camera" in cmp.command
    # the session is untouched and still renders the same
    assert dict(session.params.values()) == values
    (after,) = list(render_frames(session, size))
    np.testing.assert_array_equal(after, before)
    out = compose(cmp, "side")
    assert out.shape[1] == 3 * size[0] and out.shape[0] > size[1]


def test_a_shared_reference_cache_renders_each_reference_once():
    """A report compares its first method with each other: with one cache, the first method's
    reference (materials: 8×8 supersampled rings, which judges the ring filter) is rendered by
    the first comparison only, and the error the second one reports against it is the same."""
    cache: dict = {}
    said: list[list[str]] = [[], []]
    runs = []
    for i in range(2):
        runs.append(compare("materials", ["materials.filter_rings=false"],
                            ["materials.filter_rings=true"], size=(32, 18), rounds=1,
                            reference_cache=cache, progress=said[i].append))
    first, second = ([t for t in s if t.startswith("rendering the reference")] for s in said)
    # both sides' reference is the same (hard edges, supersampled): once, then never again
    assert len(first) == 1 and second == []
    assert runs[1].a.error == runs[0].a.error and runs[1].b.error == runs[0].b.error
    assert runs[0].a.error is not None and runs[0].a.error > 0
