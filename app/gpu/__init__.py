"""Thin layer over moderngl: contexts, the shader library, render targets, timing."""
