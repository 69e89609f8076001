"""The heads-up display: what the viewer needs to read a frame (scene, time, frame, method)."""
from __future__ import annotations

from .. import palette
from .raster import draw_text


def method_label(scene) -> str:
    if scene.method == "ccd":
        return "ccd (exact)"
    label = "discrete" if scene.substeps == 1 else f"discrete x{scene.substeps} substeps"
    if scene.world is not None and scene.world.n >= 2:
        label += f" | {scene.broadphase}"
    return label


def hud_lines(scene, state, compact: bool = False) -> list:
    """The panel's own clock: its sample index counts frames at the panel's fps. A compact HUD
    (narrow panels) keeps the clock and the collision count."""
    clock = f"t = {state.time:6.3f} s   frame {state.sample}/{scene.frames} at {scene.fps:g} fps"
    if compact:
        return [f"t = {state.time:5.2f} s  frame {state.sample}", f"collisions: {state.total_collisions}"]
    lines = [clock, method_label(scene)]
    if scene.world.n >= 2:
        lines.append(f"pairs: {state.candidates} candidates, {state.pair_hits} hits")
    lines.append(f"collisions: {state.total_collisions}")
    return lines


def draw_hud(canvas, rect, lines: list, scale: float) -> None:
    """One line in the strip below the panel's box."""
    left, top, _, height = rect
    draw_text(canvas, "   |   ".join(lines), (left + 10, top + height - 9), scale=scale, color_rgb=palette.DIM_TEXT)
