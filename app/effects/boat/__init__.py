"""The sailing boat of the maritime thesis (spec/000 §1.3–1.5): hull, rig, sails and flag that
float, steer and sail on the frame's water and wind. Shaders in ``glsl/boat/``; the simulation
in ``app/sim/boat.py`` (hull, rigid body, buoyancy, sailing, wake)."""

from .effect import Boat

__all__ = ["Boat"]
