"""The open sea (spec/000 §1.1, §1.2, §1.3): shaders in ``glsl/ocean/``, numpy reference in
``app/sim/ocean.py``; the GPU simulation in :mod:`.fft`."""

from .effect import Ocean

__all__ = ["Ocean"]
