"""The teaching tools: A/B comparison of two parameter sets of one scene, the
quality-by-budget picker over the benches' measured sweeps, the thesis digest's sections, and the
HTML handout. Runtime layer: it uses sessions and scenes, and both the window (app/ui) and the
command line use it; it never imports app.ui, app.bench or app.cli."""
