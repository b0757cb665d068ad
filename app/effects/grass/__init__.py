"""Grass (spec/003)."""

from .effect import Grass

__all__ = ["Grass"]
