"""The heads-up display: what the viewer needs to read a frame (time, frame, method, counts)."""
from __future__ import annotations

import cv2

from .. import palette
from ..core.kinds import CIRCLE
from ..model.trajectory import NOT_COUNTED
from .raster import draw_text


def method_label(trajectory) -> str:
    """How the trajectory was made, e.g. 'discrete | grid', 'ccd (exact)', 'pymunk x1'."""
    if trajectory.method == "ccd":
        return "ccd (exact)"
    if trajectory.method != "discrete":
        return f"{trajectory.method} x{trajectory.substeps}"
    label = "discrete" if trajectory.substeps == 1 else f"discrete x{trajectory.substeps} substeps"
    return label + (f" | {trajectory.broadphase}" if trajectory.broadphase else "")


def hud_lines(trajectory, frames: int, state, compact: bool = False) -> list:
    """The panel's own clock: its sample index counts frames at the trajectory's fps; this
    frame's candidate pairs and the pairs colliding in it; the collisions of every kind so far
    (one count a frame beside one running total would read as a contradiction). A compact HUD
    (narrow panels) keeps the clock and the collision count."""
    flagged = [f"approximate frames: {state.approximate_frames}"] if state.approximate_frames else []
    if compact:
        return [f"t = {state.time:5.2f} s  frame {state.sample}", f"collisions so far: {state.total_collisions}"] + flagged
    lines = [f"t = {state.time:6.3f} s   frame {state.sample}/{frames} at {trajectory.fps:g} fps",
             method_label(trajectory)]
    if trajectory.world.n >= 2:
        lines.append(f"this frame: {state.candidates} candidate pairs, {state.pair_collisions} colliding")
        lines += volume_line(trajectory, state)
    lines.append(f"collisions so far: {state.total_collisions}")
    return lines + flagged


def volume_line(trajectory, state) -> list:
    """The slides' funnel of the sample (Trajectory.hierarchy): the pairs whose bounding circles,
    boxes and oriented boxes overlap, and those that touch. The discrete engine does not count
    a world of circles, where every level is the bounding circle's, and says so."""
    counts = state.hierarchy
    if counts is not None and counts[0] != NOT_COUNTED:
        circles, boxes, oriented, touching = (int(c) for c in counts)
        return [f"volumes: {circles} circles > {boxes} boxes > {oriented} oriented > {touching} touch"]
    if trajectory.method == "discrete" and (trajectory.world.shapes == CIRCLE).all():
        return ["volumes: circles, each level exact"]
    return []


def draw_hud(canvas, rect, lines: list, scale: float, least: float = 0.0) -> tuple:
    """One line in the strip below the panel's box. A line too long for the panel shrinks, but
    not below scale `least` (the smallest readable text, render/layout.py): before that it drops
    items, the least important first (the funnel, the pairs, the method; the clock, the
    collision count and a warning of approximate frames stay). Returns (text, rectangle, scale)."""
    left, top, width, height = rect
    grow = max(1.0, scale / 0.55)   # offsets grow with the text (tall panels)
    thickness = max(1, int(round(grow)))
    room = width - 20 * grow
    kept, wanted = list(lines), scale
    text, scale = _fitted(kept, wanted, thickness, room, least)
    while _width(text, scale, thickness) > room and len(kept) > 1:
        kept.remove(max(kept, key=lambda line: _rank(lines, line)))
        text, scale = _fitted(kept, wanted, thickness, room, least)
    origin = (left + int(10 * grow), top + height - int(9 * grow))
    draw_text(canvas, text, origin, scale=scale, color_rgb=palette.DIM_TEXT, thickness=thickness)
    (w, h), base = cv2.getTextSize(text, FONT, scale, thickness)
    return text, (origin[0], origin[1] - h, w, h + base), scale


FONT = cv2.FONT_HERSHEY_SIMPLEX


def _rank(lines: list, line: str) -> int:
    """How soon a HUD item is dropped (highest first): the clock never, then the middle items
    from the last, then the collision count and a warning."""
    index = lines.index(line)
    if index == 0:
        return 0
    if line.startswith(("collisions so far:", "approximate")):
        return 1
    return 2 + index


def _width(text: str, scale: float, thickness: int) -> int:
    return cv2.getTextSize(text, FONT, scale, thickness)[0][0]


def _fitted(lines: list, scale: float, thickness: int, room: float, least: float) -> tuple:
    """The items joined, and the scale that fits them in `room` (in steps: cv2 rounds a font's
    scale, so one proportional step can leave it as wide as before), not below `least`."""
    text = "   |   ".join(lines)
    while scale * 0.95 >= max(least, 0.2) and _width(text, scale, thickness) > room:
        scale *= 0.95
    return text, scale
