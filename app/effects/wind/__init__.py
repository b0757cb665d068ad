"""The scene's one wind (spec/000 §1.4, ``Wind.cs``): speed and direction that the sea, the
clouds, the sails and the flag all read from the frame's ``wind`` slot."""

from .effect import Wind

__all__ = ["Wind"]
