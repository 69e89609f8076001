"""The slides' bounding volumes drawn over a panel (scenes/bounding_volumes.py): each body's
bounding circle, axis-aligned box and oriented box, the pairs whose volumes overlap while their
shapes do not (false positives, marked in the colour of the last volume that let them through),
and the funnel of counts per level beside the simulation.

What is drawn is what narrowphase/hierarchy.py computes for the frame's state; the funnel's
numbers are the Trajectory's (state.hierarchy, summed over the frames played by the panel's
counters). Sizes follow the panel's `unit` (render/explain.py).
"""
from __future__ import annotations

import copy
import math

import numpy as np

from .. import palette
from ..model.trajectory import LEVELS, NOT_COUNTED
from ..engine.hierarchy import CX, CY, HALF_H, HALF_W, UX, UY, XMAX, XMIN, YMAX, YMIN, hierarchy, volumes_of
from . import explain, raster
from .text import fit_width, paste, text_image, text_pixels
from .layout import nearest_point
from .structures import width

# the volumes' colours, coarsest first (the shapes themselves keep their own)
COLORS = ((94, 172, 255), (120, 220, 160), (255, 160, 60))
FALSE_POSITIVE = (240, 80, 80)
SHORT = ("circles", "boxes", "oriented boxes")   # a false positive's tag: the last volume it passed


def counters() -> dict:
    """RenderSettings.counters that sum each level's pairs over the frames played (a frame not
    counted adds nothing)."""
    return {level: _counter(k) for k, level in enumerate(LEVELS)}


def _counter(k: int):
    return lambda before, after: max(int(after.hierarchy[k]), 0) if after.hierarchy is not None else 0


def volumes_figure(world):
    """A Figure's draw (place "box") of every body's three volumes and the frame's false-positive
    and touching pairs, inside the box's outline (a body's circle at a wall reaches beyond it)."""
    def draw(canvas, rect, view, state, unit):
        _draw_volumes(canvas, view, world, state, unit)
    return draw


def _shifted(view, corner):
    """The view drawing into a region whose top-left pixel is `corner`."""
    shifted = copy.copy(view)
    shifted.origin_x, shifted.origin_y = view.origin_x - corner[0], view.origin_y - corner[1]
    return shifted


def _draw_volumes(frame, frame_view, world, state, unit) -> None:
    """The volumes, pairs and tags, drawn into the box's pixels only: the circles through a clip
    of the frame itself (the compiled rasterizer then draws into one kind of array), the rest into
    the box's region."""
    _, volumes = volumes_of(world, state.positions, state.angles)
    thin = width(unit, 0.5)
    clip = raster.box_clip(frame, frame_view, world.box)
    raster.draw_rings(frame, frame_view.to_pixels(state.positions), frame_view.length(world.radii), COLORS[0], thin,
                      clip)
    canvas, corner = raster.box_region(frame, clip)
    view = _shifted(frame_view, corner)
    raster.draw_rects(canvas, view, volumes[:, [XMIN, YMIN]], volumes[:, [XMAX, YMAX]], COLORS[1], thin)
    _oriented_boxes(canvas, view, volumes, COLORS[2], thin)
    found = hierarchy(world, state.positions, state.angles)
    pairs, levels = found["pairs"], found["levels"]
    for level in (1, 2, 3):   # passed up to this volume, then rejected: false positives
        chosen = pairs[levels == level]
        if len(chosen):
            ends = state.positions[chosen]
            raster.draw_lines(canvas, view, ends[:, 0], ends[:, 1], FALSE_POSITIVE, width(unit, 1.25))
    touching = pairs[levels == 4]
    if len(touching):
        ends = state.positions[touching]
        raster.draw_lines(canvas, view, ends[:, 0], ends[:, 1], palette.HIGHLIGHT, width(unit, 1.25))
    for level in (1, 2, 3):   # the tags last, over the lines, each where the frame's layout finds room
        for i, j in pairs[levels == level]:
            middle = frame_view.to_pixels(0.5 * (state.positions[i] + state.positions[j]))
            _tag(frame, state.layout, SHORT[level - 1], middle, unit, COLORS[level - 1])


def _oriented_boxes(canvas, view, volumes, color, thickness: int) -> None:
    """Each oriented box's outline: its centre ± half extents along its axes."""
    ux, uy = volumes[:, UX, None], volumes[:, UY, None]
    along = np.array([1.0, -1.0, -1.0, 1.0])[None] * volumes[:, HALF_W, None]
    across = np.array([1.0, 1.0, -1.0, -1.0])[None] * volumes[:, HALF_H, None]
    xs = volumes[:, CX, None] + along * ux - across * uy
    ys = volumes[:, CY, None] + along * uy + across * ux
    corners = np.stack([xs, ys], axis=-1)                       # (n, 4, 2)
    following = np.roll(corners, -1, axis=1)
    raster.draw_lines(canvas, view, corners.reshape(-1, 2), following.reshape(-1, 2), color, thickness)


def _tag(canvas, layout, text: str, centre_px, unit: float, color) -> None:
    """A false positive's tag near the middle of its pair, clear of the shapes and other tags
    (above the middle when that is free), with a leader line when moved far."""
    pixels = explain.NOTE_PIXELS * unit
    image = text_image(text, pixels)
    placed = layout.place(image.shape[::-1], centre_px, "tag", text, text_pixels(pixels), gap=3 * unit,
                          first=(0, -1))
    if placed.leader:
        start = np.asarray(centre_px, float)
        raster.draw_lines_px(canvas, [start], [nearest_point(placed.rect, start)], color, max(1, int(round(unit))))
    paste(canvas, image, placed.rect[0], placed.rect[1], color, 1.0)


def funnel_figure(canvas, rect, view, state, unit) -> None:
    """A Figure's draw (place "side"): per level, a bar as long as its share of the pairs whose
    bounding circles overlapped, over every frame played so far, with the count and the share of
    false positives (passing pairs whose shapes do not touch), and this frame's count."""
    x, y, w, h = rect
    totals = [state.counters.get(level, 0) for level in LEVELS]
    now = state.hierarchy if state.hierarchy is not None else np.full(4, NOT_COUNTED)
    pad = explain.margin(unit)
    row = (h - 3 * pad) / (len(LEVELS) + 1)
    room = w - 2 * pad
    _text(canvas, "the funnel, all frames so far", x + pad, y + pad, unit, palette.TEXT, room, state.layout, rect)
    for k, level in enumerate(LEVELS):
        top = y + 2 * pad + (k + 1) * row
        false = 1.0 - totals[3] / totals[k] if totals[k] else math.nan
        share = totals[k] / totals[0] if totals[0] else 0.0
        color = COLORS[k] if k < 3 else palette.HIGHLIGHT
        # the shapes are tested at frame times, where bodies that collided within a step have
        # already parted: that level is said apart from the collisions, lest 0 read as none
        label = f"{level}: {totals[k]}" if k < 3 else f"shapes touching at a frame: {totals[k]}"
        _text(canvas, label, x + pad, top - 0.55 * row, unit, color, room, state.layout, rect)
        bar = max(share * room, 1.0)
        raster.draw_rect_px(canvas, (x + pad, top - 0.2 * row), (x + pad + bar, top + 0.05 * row), color, -1)
        note = f"now {now[k]}" if now[k] != NOT_COUNTED else ""
        if k == 3:
            note += f"; {state.total_collisions} collisions, within steps"
        if k < 3 and not math.isnan(false):
            note += f", {false:.0%} false positives"
        _text(canvas, note, x + pad, top + 0.12 * row, unit, palette.DIM_TEXT, room, state.layout, rect)


def _text(canvas, text: str, left: float, top: float, unit: float, color, room: float, layout, bound) -> None:
    """A line of the funnel, shrunk to its room, and kept in the frame's layout (measured)."""
    if text:
        pixels = explain.NOTE_PIXELS * unit
        typeset = text_image(text, pixels)
        image = fit_width(typeset, room)
        rect = paste(canvas, image, int(round(left)), int(round(top)), color, 1.0)
        if layout is not None:
            layout.keep("funnel", text, rect, text_pixels(pixels) * image.shape[1] / typeset.shape[1], bound)
