"""CPU-side numpy code with no GL: sun and moon, camera, and (later) spectra and buoyancy."""
