"""Where a frame's labels go: notes, marks, arrow labels, tags and status lines placed away from
the box's lines, the bodies and each other, and inside the simulation's rectangle.

A placer as maps place town names: each label has an anchor (the point it names) and candidate
positions around it, nearest first; the first candidate whose rectangle stays within the bound
and meets no obstacle wins. Obstacles are the box's edges and segments (lines with a width), the
bodies of the frame's sample (discs; a polygon by its bounding circle), what the explainer adds
(an arrow's shaft, the disc a note's point stands for) and the labels placed before. A label put
far from its anchor gets a leader line. The candidates' order is fixed, so the same frame places
its labels the same way every time.

The player makes one Layout per panel and frame (`Layout.of_frame`), hands it to overlays and
figures as `state.layout`, and keeps what was placed (`Layout.placed`) for the tests.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

BASE_HEIGHT = 480.0        # a frame this tall draws text at its base size (render/explain.py too)
MIN_TEXT_PIXELS = 11.0     # the smallest text (its size in pixels, an em) in a frame BASE_HEIGHT tall
CAP_SHARE = 0.73           # a capital's height over the text's size (DejaVu Sans, mathtext's font)
HERSHEY_CAP = 21.0         # a capital of OpenCV's Hershey simplex font at scale 1, in pixels
SQRT_HALF = math.sqrt(0.5)
# the directions tried around an anchor, in order (x right, y down): right, left, the diagonals, up, down
DIRECTIONS = ((1, 0), (-1, 0), (1, -1), (1, 1), (-1, -1), (-1, 1), (0, -1), (0, 1))


def min_text_pixels(frame_height: float) -> float:
    """The smallest text size allowed in a frame this tall: MIN_TEXT_PIXELS at 480 rows, in
    proportion above and below (a 1080p frame shown full screen reads like a 480p one)."""
    return MIN_TEXT_PIXELS * frame_height / BASE_HEIGHT


def hershey_pixels(scale: float) -> float:
    """The size (em) of OpenCV's Hershey text drawn at `scale`, in the units of mathtext's sizes:
    its capital's height over CAP_SHARE."""
    return HERSHEY_CAP * scale / CAP_SHARE


@dataclass(frozen=True)
class Placed:
    """A label as drawn: kind ("note", "mark", "arrow", "tag", "status", "caption", "hud"), its
    text, its rectangle (x, y, w, h) in pixels, the pixel point it names (None for a status line,
    a caption or the HUD), its text size in pixels, the rectangle it must stay in, and whether a
    free place was found (False: none was, and it sits where it meets the fewest obstacles)."""
    kind: str
    text: str
    rect: tuple
    anchor: tuple
    pixels: float
    bound: tuple
    fits: bool = True
    leader: bool = False


class Layout:
    """The obstacles of one panel's frame and the labels placed in it so far."""

    def __init__(self, bound: tuple, pad: float = 2.0):
        self.bound, self.pad = tuple(float(v) for v in bound), float(pad)
        self.lines = np.zeros((0, 5))    # x0, y0, x1, y1, half width
        self.discs = np.zeros((0, 3))    # x, y, radius
        self.placed: list = []
        self.unit = 1.0   # the panel's scale (render/explain.py), for text placed by an overlay

    @classmethod
    def of_frame(cls, view, world, positions, unit: float) -> "Layout":
        """The box's edges, the world's segments and the sample's bodies, in `view`'s pixels."""
        layout = cls(view.rect, pad=2.0 * unit)
        layout.unit = unit
        xmin, ymin, xmax, ymax = world.box
        corners = view.to_pixels([[xmin, ymin], [xmax, ymin], [xmax, ymax], [xmin, ymax]])
        layout.add_lines(corners, np.roll(corners, -1, axis=0), 1.5)
        if len(world.segments):
            segments = np.asarray(world.segments, float).reshape(-1, 4)
            layout.add_lines(view.to_pixels(segments[:, :2]), view.to_pixels(segments[:, 2:]), 2.0)
        layout.add_discs(view.to_pixels(positions), view.length(world.radii))
        return layout

    def add_lines(self, starts, ends, half_width: float) -> None:
        starts, ends = np.asarray(starts, float).reshape(-1, 2), np.asarray(ends, float).reshape(-1, 2)
        rows = np.column_stack([starts, ends, np.full(len(starts), float(half_width))])
        self.lines = np.vstack([self.lines, rows])

    def add_discs(self, centres, radii) -> None:
        centres = np.asarray(centres, float).reshape(-1, 2)
        radii = np.broadcast_to(np.asarray(radii, float), (len(centres),))
        self.discs = np.vstack([self.discs, np.column_stack([centres, radii])])

    def place(self, size: tuple, anchor, kind: str, text: str, pixels: float, gap: float = 0.0,
              first=None) -> Placed:
        """Place a label of `size` (w, h) naming pixel point `anchor`, at least `gap` pixels from
        it; `first`, a direction of DIRECTIONS, is tried before the others at every distance."""
        w, h = size
        ax, ay = float(anchor[0]), float(anchor[1])
        directions = list(DIRECTIONS)
        if first is not None:
            directions.remove(tuple(first))
            directions.insert(0, tuple(first))
        reach = max(self.bound[2], self.bound[3])
        distances = gap + self.pad + np.arange(0.0, reach, max(0.25 * h, 2.0))
        xs, ys = [], []
        for d in distances:   # nearest first; at each distance every direction in turn
            for dx, dy in directions:
                step = d * (SQRT_HALF if dx and dy else 1.0)
                xs.append(ax + dx * step - (w if dx < 0 else 0.5 * w if dx == 0 else 0.0))
                ys.append(ay + dy * step - (h if dy < 0 else 0.5 * h if dy == 0 else 0.0))
        rects = np.column_stack([np.round(xs), np.round(ys), np.full(len(xs), w), np.full(len(xs), h)])
        chosen, fits = self._choose(rects)
        x, y = int(rects[chosen, 0]), int(rects[chosen, 1])
        far = math.hypot(*(nearest_point((x, y, w, h), (ax, ay)) - (ax, ay))) > gap + self.pad + 1.5 * h
        return self._keep(Placed(kind, text, (x, y, int(w), int(h)), (ax, ay), pixels, self.bound, fits, far))

    def status(self, size: tuple, kind: str, text: str, pixels: float) -> Placed:
        """Place a line that names no point: the free place nearest the bound's top-left corner,
        row by row from the top (a status line kept clear of the bodies)."""
        w, h = size
        bx, by, bw, bh = self.bound
        step = max(0.5 * h, 2.0)
        tops = by + self.pad + np.arange(0.0, bh - h - 2 * self.pad + 1, step)
        lefts = bx + self.pad + np.arange(0.0, max(bw - w - 2 * self.pad, 0.0) + 1, step)
        ys, xs = np.meshgrid(tops, lefts, indexing="ij")
        rects = np.column_stack([np.round(xs.ravel()), np.round(ys.ravel()),
                                 np.full(xs.size, w), np.full(xs.size, h)])
        chosen, fits = self._choose(rects)
        x, y = int(rects[chosen, 0]), int(rects[chosen, 1])
        return self._keep(Placed(kind, text, (x, y, int(w), int(h)), None, pixels, self.bound, fits))

    def keep(self, kind: str, text: str, rect: tuple, pixels: float, bound: tuple) -> Placed:
        """Record a label placed by its own rule (a caption in its strip, the HUD): it is only
        measured, and later labels keep clear of it."""
        return self._keep(Placed(kind, text, tuple(int(v) for v in rect), None, pixels, tuple(bound)))

    def _keep(self, placed: Placed) -> Placed:
        self.placed.append(placed)
        return placed

    def _choose(self, rects: np.ndarray) -> tuple:
        """The index of the first rectangle (n, 4) that is free, and True; else of the one
        meeting the fewest obstacles, and False."""
        hits = self.obstacles_met(rects)
        free = np.flatnonzero(hits == 0)
        if len(free):
            return int(free[0]), True
        return int(np.argmin(hits)), False

    def obstacles_met(self, rects: np.ndarray) -> np.ndarray:
        """(n,) how many obstacles each rectangle (n, 4) meets, a rectangle leaving the bound
        counting as one."""
        x, y, w, h = (rects[:, k] for k in range(4))
        bx, by, bw, bh = self.bound
        hits = ((x < bx) | (y < by) | (x + w > bx + bw) | (y + h > by + bh)).astype(np.int64)
        p = self.pad
        if len(self.discs):   # every rectangle against every disc at once: its point nearest the centre
            cx, cy, r = (self.discs[None, :, k] for k in range(3))
            dx = np.clip(cx, (x - p)[:, None], (x + w + p)[:, None]) - cx
            dy = np.clip(cy, (y - p)[:, None], (y + h + p)[:, None]) - cy
            hits += np.count_nonzero(dx * dx + dy * dy < r * r, axis=1)
        for x0, y0, x1, y1, half in self.lines:
            grow = p + half
            hits += segment_meets_rects(x0, y0, x1, y1, x - grow, y - grow, x + w + grow, y + h + grow)
        for other in self.placed:
            ox, oy, ow, oh = other.rect
            hits += (x < ox + ow + p) & (ox < x + w + p) & (y < oy + oh + p) & (oy < y + h + p)
        return hits


def segment_meets_rects(x0, y0, x1, y1, left, top, right, bottom) -> np.ndarray:
    """(n,) does the segment (x0, y0)-(x1, y1) meet each rectangle [left, right] x [top, bottom]
    (arrays)? Liang-Barsky: clip the segment's parameter range to each slab in turn."""
    low, high = np.zeros(np.shape(left)), np.ones(np.shape(left))
    for start, delta, lo, hi in ((x0, x1 - x0, left, right), (y0, y1 - y0, top, bottom)):
        if abs(delta) < 1e-12:
            outside = (start < lo) | (start > hi)
            high = np.where(outside, -1.0, high)
            continue
        t0, t1 = (lo - start) / delta, (hi - start) / delta
        low, high = np.maximum(low, np.minimum(t0, t1)), np.minimum(high, np.maximum(t0, t1))
    return low <= high


def nearest_point(rect: tuple, point) -> np.ndarray:
    """The point of rectangle (x, y, w, h) nearest `point`."""
    x, y, w, h = rect
    return np.array([min(max(point[0], x), x + w), min(max(point[1], y), y + h)], float)
