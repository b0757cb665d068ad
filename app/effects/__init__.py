"""Effects: one package per effect (``app/effects/<name>/``, the Effect class in its
``effect.py``), named like its GLSL folder (``glsl/<name>/``), its numpy twins
(``app/sim/<name>.py``) and its tests. Effects never import one another; they meet through the
frame's slots (``app.frame``). The interface is :class:`app.effects.base.Effect`."""
