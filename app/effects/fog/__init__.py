"""Fog (spec/003)."""

from .effect import Fog

__all__ = ["Fog"]
