"""The desktop window: ImGui panels built from parameters, HUD, key maps."""
