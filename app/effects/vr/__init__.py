"""VR mode (spec/003)."""

from .effect import Vr

__all__ = ["Vr"]
