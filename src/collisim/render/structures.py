"""Tutorial drawings of the broad phases' structures (scenes/broadphase_six.py): sweep and
prune's intervals, the uniform grid's cells and their counts, the kd-tree's splits, the BVH's
boxes, and the grid's memory against its cell size as a chart.

Every function draws what a broad phase reported (`broadphase.describe`, or the engine's own
grid kernels); none decides anything. Sizes are in units of the panel's `unit` (explain.py),
so lines and labels read at -ql and at 4K.
"""
from __future__ import annotations

import io

import numpy as np

from .. import palette
from ..broadphase.grid import bin_boxes
from ..broadphase.step import GridState
from . import explain, raster
from .text import paste, text_image


def width(unit: float, share: float = 1.0) -> int:
    """A line `share` times the standard width, in whole pixels, at least 1."""
    return max(1, int(round(2.0 * share * unit)))


def dimmed(color, amount: float = 0.6) -> tuple:
    """A colour moved `amount` of the way toward the background."""
    return tuple(int(round((1 - amount) * c + amount * b)) for c, b in zip(color, palette.BACKGROUND))


def pair_lines(canvas, view, positions, pairs, color, line: int) -> None:
    """A line between the centres of each pair (k, 2)."""
    pairs = np.asarray(pairs, np.intp).reshape(-1, 2)
    if len(pairs):
        raster.draw_lines(canvas, view, positions[pairs[:, 0]], positions[pairs[:, 1]], color, line)


def rings(canvas, view, positions, radii, bodies, color, unit: float, share: float = 1.0) -> None:
    """A ring just outside each of `bodies`."""
    bodies = list(bodies)
    if bodies:
        raster.draw_rings(canvas, view.to_pixels(positions[bodies]), view.length(radii[bodies]) + 3 * unit,
                          color, width(unit, share))


def label(canvas, text: str, centre_px, unit: float, color=None, pixels: float = explain.NOTE_PIXELS) -> tuple:
    """Typeset text centred on a pixel point; returns its rectangle."""
    image = text_image(text, pixels * unit)
    left = int(round(centre_px[0] - image.shape[1] / 2))
    top = int(round(centre_px[1] - image.shape[0] / 2))
    return paste(canvas, image, left, top, color or palette.TEXT, 1.0)


# --- sweep and prune -------------------------------------------------------------------------

def sweep_lanes(canvas, rect, view, intervals, order, shown: int, active, current, colors, unit,
                outline: bool = True) -> None:
    """Each box's interval on the sweep axis (x, sharing the view's x scale) in its own lane, in
    sorted order top to bottom: the first `shown` of the sorted list, those in `active` in their
    colour and the rest dimmed, the span of the active list outlined (if `outline`), and the sweep line at the
    start of box `current` (None: no sweep line)."""
    inset = int(round(0.5 * explain.margin(unit)))   # clear of the strip's edges (the frame's, under a lane)
    x, y, w, h = rect[0], rect[1] + inset, rect[2], rect[3] - 2 * inset
    lane = h / max(len(order), 1)
    line = max(2, int(round(0.45 * lane)))
    ends = view.to_pixels(np.column_stack([intervals.ravel(), np.zeros(intervals.size)]))[:, 0].reshape(-1, 2)
    ends = np.clip(ends, x + line, x + w - line)
    layer = canvas[y:y + h, x:x + w]   # a view: nothing drawn here leaves the strip
    for rank, body in enumerate(order[:shown]):
        middle = (rank + 0.5) * lane
        color = colors[body] if body in active else dimmed(colors[body], 0.7)
        raster.draw_lines_px(layer, [(ends[body, 0] - x, middle)], [(ends[body, 1] - x, middle)], color, line)
    if outline and len(active):
        span, edge = ends[list(active)], width(unit, 0.75)
        raster.draw_rect_px(layer, (span[:, 0].min() - x - line, edge), (span[:, 1].max() - x + line, h - 1 - edge),
                            palette.HIGHLIGHT, edge)
    if current is not None:
        at = ends[current, 0] - x
        raster.draw_lines_px(layer, [(at, 0)], [(at, h - 1)], palette.HIGHLIGHT, width(unit, 0.75))


# --- uniform grid ----------------------------------------------------------------------------

def grid_lines(canvas, view, box, grid: GridState, unit) -> None:
    """The grid's cell edges across the world's box (the engine's grid covers the box)."""
    xmin, ymin, xmax, ymax = box
    size = 1.0 / grid.cells_per_unit
    xs = np.clip(grid.origin[0] + size * np.arange(grid.nx + 1), xmin, xmax)
    ys = np.clip(grid.origin[1] + size * np.arange(grid.ny + 1), ymin, ymax)
    color, line = palette.DIM_TEXT, width(unit, 0.75)
    raster.draw_lines(canvas, view, np.column_stack([xs, np.full_like(xs, ymin)]),
                      np.column_stack([xs, np.full_like(xs, ymax)]), color, line)
    raster.draw_lines(canvas, view, np.column_stack([np.full_like(ys, xmin), ys]),
                      np.column_stack([np.full_like(ys, xmax), ys]), color, line)


def cell_members(lo, hi, grid: GridState) -> tuple:
    """The boxes filed in each cell by the engine's own binning (cell id ix * ny + iy), and the
    bytes its two arrays take (cell starts and entries: the grid's memory)."""
    start, boxes = bin_boxes(lo, hi, grid.origin, grid.cells_per_unit, grid.nx, grid.ny)
    return [boxes[start[c]:start[c + 1]] for c in range(grid.nx * grid.ny)], start.nbytes + boxes.nbytes


def cell_counts(canvas, view, box, grid: GridState, counts, positions, radii, unit) -> list:
    """Each non-empty cell's count in a small tag at the corner of the cell (inside the box)
    farthest from every disc, so no number sits on a particle. Returns the tags' rectangles."""
    size, drawn = 1.0 / grid.cells_per_unit, []
    inset = 0.28 * np.min(radii)
    for cell, count in enumerate(counts):
        if count == 0:
            continue
        ix, iy = divmod(cell, grid.ny)
        x0, y0 = grid.origin + size * np.array([ix, iy])
        x1, y1 = min(x0 + size, box[2]), min(y0 + size, box[3])
        corners = np.array([[x0 + inset, y0 + inset], [x1 - inset, y0 + inset],
                            [x0 + inset, y1 - inset], [x1 - inset, y1 - inset]])
        gaps = np.linalg.norm(corners[:, None] - positions[None], axis=2) - radii[None]
        corner = corners[np.argmax(gaps.min(axis=1))]
        drawn.append(label(canvas, str(int(count)), view.to_pixels(corner), unit, palette.HIGHLIGHT))
    return drawn


def grid_chart(sizes, memory, tests, engine_size, pixels: tuple) -> np.ndarray:
    """An RGB image (h, w, 3) of the grid's memory (bytes) and its pair tests against cell size,
    the engine's cell size marked: the trade-off, fewer cells cost more tests."""
    import matplotlib
    import matplotlib.ticker
    from matplotlib.figure import Figure   # no pyplot: a user's backend and figures stay untouched
    w, h = pixels
    text, background = np.array(palette.TEXT) / 255, np.array(palette.BACKGROUND) / 255
    with matplotlib.rc_context({"font.size": 15, "text.color": text, "axes.labelcolor": text, "xtick.color": text,
                         "ytick.color": text, "axes.edgecolor": text, "axes.facecolor": background,
                         "figure.facecolor": background}):
        figure = Figure(figsize=(w / 100, h / 100), dpi=100)
        top, bottom = figure.subplots(2, 1, sharex=True)
        top.plot(sizes, memory, "o-", color=np.array(palette.HIGHLIGHT) / 255)
        top.set_ylabel("memory (bytes)")
        bottom.plot(sizes, tests, "o-", color=np.array((120, 220, 160)) / 255)
        bottom.set_ylabel("pair tests")
        bottom.set_xlabel("cell size (world units)")
        for axes in (top, bottom):
            axes.axvline(engine_size, color=text, linestyle=":", linewidth=1.5)
        bottom.yaxis.set_major_locator(matplotlib.ticker.MaxNLocator(integer=True))
        top.annotate("the engine's", (engine_size, 0.95), xycoords=("data", "axes fraction"), ha="left",
                     va="top", fontsize=13, xytext=(4, 0), textcoords="offset points")
        top.set_title("the grid's trade-off", fontsize=16)
        figure.tight_layout()
        buffer = io.BytesIO()
        figure.savefig(buffer, format="png", facecolor=background)
    import cv2
    image = cv2.imdecode(np.frombuffer(buffer.getvalue(), np.uint8), cv2.IMREAD_COLOR)
    return image[:, :, ::-1].copy()


# --- trees -----------------------------------------------------------------------------------

def kd_splits(canvas, view, splits, shown: int, unit, newest: bool = True) -> None:
    """The first `shown` splits, each a line across its node's region; the newest highlighted
    (if `newest`)."""
    for k, (axis, value, node_lo, node_hi, depth) in enumerate(splits[:shown]):
        start, end = np.array(node_lo, float), np.array(node_hi, float)
        start[axis] = end[axis] = value
        lit = newest and k == shown - 1
        raster.draw_lines(canvas, view, [start], [end], palette.HIGHLIGHT if lit else palette.BOX,
                          width(unit, 1.25 if lit else max(0.5, 1.0 - 0.2 * depth)))


def bvh_boxes(canvas, view, nodes, depth: int, lit=(), unit: float = 1.0, newest: bool = True) -> None:
    """The nodes down to `depth` (the deepest highlighted if `newest`, shallower ones dimmer),
    and the boxes of the nodes in `lit` filled."""
    for node_lo, node_hi, node_depth, _ in nodes:
        if node_depth > depth:
            continue
        color = palette.HIGHLIGHT if newest and node_depth == depth else \
            dimmed(palette.BOX, 0.15 * (depth - node_depth))
        raster.draw_rects(canvas, view, [node_lo], [node_hi], color, width(unit, 0.75))
    if len(lit):
        layer = canvas.copy()
        for k in lit:
            raster.draw_rects(layer, view, [nodes[k][0]], [nodes[k][1]], palette.HIGHLIGHT, -1)
        explain.blend(canvas, layer, 0.35)
