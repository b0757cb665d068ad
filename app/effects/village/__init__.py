"""The Fracsland village (spec/003)."""

from .effect import Village

__all__ = ["Village"]
