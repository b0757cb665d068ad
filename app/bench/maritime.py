"""``natura bench maritime``'s sweep: the maritime thesis's clouds (model B, ``clouds_b``)
amortised as the field renders them — ms of the march pass against the error of the image,
still and during a 30°/s pan, for each march resolution and refresh fraction, against the
full-resolution march averaged over its jittered offsets (app/bench/amortise.py has the
method). Written beside the JSON as ``<report>.png``.
"""

from __future__ import annotations

from . import amortise, at_most, write_chart

#: the sweep's size, never above the bench's ``--size``
SWEEP_SIZE = (320, 180)


def sweep(session, size, warmup: int = 1, repeat: int = 3, sizes=None) -> dict:
    """The sweep from the chase camera's eye, held there: the chase camera reads a turn of the
    view as an orbit about the boat, so a pan would also move the eye (and, row after row, take
    it down under the waves)."""
    p = session.params
    mode = p["maritime.camera"]
    session.scene.frame(at_most(size, SWEEP_SIZE), 0.0)  # the chase camera's eye, placed
    p.set("maritime.camera", "free")
    try:
        return {"amortised": amortise.sweep(session, "clouds_b", at_most(size, SWEEP_SIZE),
                                            warmup, repeat)}
    finally:
        p.set("maritime.camera", mode)


def chart(report: dict, path, force: bool = False) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(1, 1, figsize=(8, 5))
    amortise.plot(ax, report["sweep"]["amortised"])
    write_chart(fig, path, force, title=f"natura bench maritime — {report['renderer']}")


def summary(report: dict) -> str:
    return "\n".join(amortise.summary(report["sweep"]["amortised"]))
