"""The scene's one wind (spec/000 §1.4, ``Wind.cs``): a speed and a direction that every effect
of the scene reading the frame's ``wind`` slot follows."""

from .effect import Wind

__all__ = ["Wind"]
