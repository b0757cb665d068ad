"""The surfaces lab (spec/003 §2.4–2.8): transparency and render queues, reflection probes with
box and sphere correction, metallic and dielectric, refraction and Fresnel, and the shared
shadow module's directional, point and spot maps — each against an exact reference. Shaders in
``glsl/surfaces/`` (and the shared ``glsl/common/shadow*.glsl``, ``fresnel.glsl``); the analytic
scene and its ray casting in ``app/sim/surfaces_scene.py``."""

from .effect import Surfaces

__all__ = ["Surfaces"]
