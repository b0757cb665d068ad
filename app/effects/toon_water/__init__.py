"""Stylised water (spec/003)."""

from .effect import ToonWater

__all__ = ["ToonWater"]
