"""Helpers shared by effects that are not effects: compositing layers, meshes, noise textures,
environment fallbacks and shadow maps. They may use ``app.gpu`` and ``app.sim``, never an effect."""
