"""The example effect of docs/architecture.md (in your own project: app/effects/vignette/)."""

from .effect import Vignette

__all__ = ["Vignette"]
