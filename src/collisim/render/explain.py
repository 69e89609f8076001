"""The explainer layer: captions, typeset formulas, arrows and numbered particles that appear and
fade on a panel's timeline, for scenes that teach.

A scene asks for it with `RenderSettings(explainer=Explainer([...]))`. Its items (defined and
checked in render/items.py, imported here):

* `Caption(text, start, end, strip="bottom", line=0)`: a line in a strip above or below the
  simulation, never over it. Text between dollar signs is typeset as math by matplotlib's
  mathtext (no TeX install needed): "the update $p \\leftarrow p + v\\,\\Delta t$".
* `Arrow(tail, head, start, end, label="")`: an arrow in world units; tail and head are points
  or functions of the frame's state (FrameState), so an arrow can follow a body.
* `Mark(bodies, start, end, labels=None)`: numbers bodies (or labels them) beside them, with a
  ring, so a caption can name "particle 2".
* `Note(text, at, start, end)`: a short label next to a world point; the text and the point
  may be functions of the state.
* `Figure(draw, start, end, place="side")`: a picture of the scene's own drawn by
  `draw(canvas, rect, view, state, unit)` inside a region beside the simulation: the "side"
  column (`Explainer(side=0.3)` reserves that share of the panel's width at the right) or a
  caption strip ("top", "bottom", which then holds no captions), or "box", the simulation's
  own area (a structure drawn over the bodies). A strip figure shares the view's x axis, so it
  can show a projection of the bodies (sweep and prune's intervals).
  `image_figure(make_image)` draws an RGB image made once (a matplotlib chart) fitted to it.

Times are the panel's simulation time in seconds, or functions of the frame's state (so an
item can wait for an event the engine found); an item fades in and out over `fade` seconds.
A caption's text may also be a function of the state, for numbers read off the trajectory.
Sizes follow the panel: text, lines and margins scale with its height, so the same scene reads
at 854x480 and at 4K. Each draw records the rectangles it filled (`drawn`: (kind, rect,
bound)), so a test can check that no text leaves its strip or panel.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Callable, Union

import cv2
import numpy as np

from .. import palette
from . import layout as placing, raster
from .text import fit_width, paste, split_line, text_image, text_pixels, two_lines
from ..core.checks import is_whole
from .items import Arrow, Caption, Figure, Mark, Note, Point, check_choice

BASE_HEIGHT = placing.BASE_HEIGHT   # a panel this tall draws text at its base size
CAPTION_PIXELS = 17.0      # caption text height at the base size
NOTE_PIXELS = 14.0
MIN_UNIT = placing.MIN_TEXT_PIXELS / NOTE_PIXELS   # the smallest text, a note's, at its least readable size


@dataclass
class Explainer:
    """Timed items over a panel; `lines` per strip sets the strips' height (a number for both,
    or (top, bottom)); `side` is the share of the panel's width kept for side figures."""
    items: list
    fade: float = 0.25
    lines: Union[int, tuple] = 2
    side: float = 0.0
    clock: str = "simulation"    # items' times in "simulation" seconds, or "video" seconds (freezes)
    drawn: list = field(default_factory=list, repr=False)

    def __post_init__(self):
        kinds = (Caption, Arrow, Mark, Note, Figure)
        strange = [item for item in self.items if not isinstance(item, kinds)]
        if strange:
            raise ValueError(f"an Explainer holds Caption, Arrow, Mark, Note and Figure items, got {strange[0]!r}")
        lines = self.lines if isinstance(self.lines, tuple) else (self.lines, self.lines)
        if len(lines) != 2 or not all(is_whole(k) for k in lines):
            raise ValueError(f"Explainer lines must be a whole number >= 0, or two (top, bottom), got {self.lines!r}")
        if not (isinstance(self.fade, (int, float)) and 0 <= self.fade < math.inf):
            raise ValueError(f"Explainer fade must be seconds >= 0, got {self.fade!r}")
        if not (isinstance(self.side, (int, float)) and 0 <= self.side < 1):
            raise ValueError(f"Explainer side must be a share of the width in [0, 1), got {self.side!r}")
        check_choice(self, "clock", ("simulation", "video"))

    def check_bodies(self, n: int) -> None:
        """ValueError when a Mark names a body the panel's world (of n bodies) lacks."""
        for item in self.items:
            if isinstance(item, Mark) and max(item.bodies) >= n:
                raise ValueError(f"Mark names body {max(item.bodies)}, and the world has {n} bodies (0 to {n - 1})")

    def strips(self) -> tuple:
        """(top lines, bottom lines) the panel must reserve."""
        used = {item.strip for item in self.items if isinstance(item, Caption)}
        used |= {item.place for item in self.items if isinstance(item, Figure)}
        top, bottom = self.lines if isinstance(self.lines, tuple) else (self.lines, self.lines)
        return (top if "top" in used else 0, bottom if "bottom" in used else 0)

    def opacity(self, item, state) -> float:
        """1 while the item shows, 0 outside, fading in and out over `fade`. An item's start
        and end are seconds, or functions of the frame's state giving seconds (None: not yet),
        so an item can wait for what the engine found, e.g. the first bounce in state.events;
        the first time such a function answers, its answer is kept."""
        start, end = self._moment(item, "start", state), self._moment(item, "end", state)
        time = state.clock if self.clock == "video" else state.time
        if self.fade <= 0:
            return float(start <= time <= end)
        rise = (time - start) / self.fade + 1.0
        fall = (end - time) / self.fade + 1.0
        return float(min(max(min(rise, fall), 0.0), 1.0))

    def _moment(self, item, name: str, state) -> float:
        value = getattr(item, name)
        if not callable(value):
            return moment(value, state)
        key = ("explainer moment", id(item), name)   # kept for the panel's play, not beyond it
        if key not in state.memory:
            found = value(state)
            if found is None:
                return math.inf
            state.memory[key] = float(found)
        return state.memory[key]

    def draw(self, canvas, view, state, world, strip_rects: dict, unit: float) -> None:
        """Draw every item visible at state.time. strip_rects: {"top"|"bottom": (x, y, w, h)};
        unit: the panel's scale (its height / BASE_HEIGHT); world: the panel's World (radii)."""
        self.drawn = []
        layout = getattr(state, "layout", None)
        if layout is None:   # drawn outside a player (a test's frame): the layout of this frame alone
            layout = state.layout = placing.Layout.of_frame(view, world, state.positions, unit)
        shown = [(item, alpha) for item in self.items if (alpha := self.opacity(item, state)) > 0.0]
        self._obstacles(layout, view, state, [item for item, _ in shown], unit)
        for item, alpha in shown:
            if isinstance(item, Caption):
                self._caption(canvas, state, item, strip_rects[item.strip], unit, alpha)
            elif isinstance(item, Arrow):
                self._arrow(canvas, view, state, item, unit, alpha)
            elif isinstance(item, Mark):
                self._mark(canvas, view, state, world.radii, item, unit, alpha)
            elif isinstance(item, Note):
                text = item.text(state) if callable(item.text) else item.text
                if text:
                    self._note(canvas, view, state, text, resolve(item.at, state), unit, alpha, item.gap, dot=True)
            elif isinstance(item, Figure):
                self._figure(canvas, view, state, item, strip_rects[item.place], unit, alpha)

    @staticmethod
    def _obstacles(layout, view, state, items, unit) -> None:
        """What labels keep clear of besides the box and the bodies: each shown note's point
        with the disc of its gap (a ring the scene draws there), and each arrow's shaft."""
        for item in items:
            if isinstance(item, Note):
                layout.add_discs(view.to_pixels(resolve(item.at, state)), max(float(view.length(item.gap)), 3 * unit))
            elif isinstance(item, Arrow):
                tail, head = view.to_pixels(resolve(item.tail, state)), view.to_pixels(resolve(item.head, state))
                if np.all(np.isfinite(tail)) and np.all(np.isfinite(head)):
                    layout.add_lines(tail, head, thickness(unit))

    def _figure(self, canvas, view, state, item, rect, unit, alpha):
        """Draw on a copy, blend it in, and record the box of the pixels it changed (what the
        tests hold to the figure's region)."""
        layer = canvas.copy()
        item.draw(layer, rect, view, state, unit)
        changed = changed_rect(canvas, layer)
        if changed is not None:
            self.drawn.append(("figure", changed, rect))
        blend(canvas, layer, alpha)

    def _caption(self, canvas, state, item, rect, unit, alpha):
        x, y, w, h = rect
        line_height = h / self.strips()[item.strip == "bottom"]
        text = item.text(state) if callable(item.text) else item.text
        if not text:
            return
        typeset = text_image(text, CAPTION_PIXELS * unit)
        image = fit_width(typeset, w - 2 * margin(unit))
        top = int(round(y + item.line * line_height + 0.5 * (line_height - image.shape[0])))
        left = int(round(x + margin(unit)))
        drawn = paste(canvas, image, left, top, palette.TEXT, alpha)
        self.drawn.append(("caption", drawn, rect))
        pixels = text_pixels(CAPTION_PIXELS * unit) * image.shape[1] / typeset.shape[1]
        state.layout.keep("caption", text, drawn, pixels, rect)

    def _arrow(self, canvas, view, state, item, unit, alpha):
        tail, head = view.to_pixels(resolve(item.tail, state)), view.to_pixels(resolve(item.head, state))
        if not (np.all(np.isfinite(tail)) and np.all(np.isfinite(head))):
            return   # an end not known (a velocity a positions-only trajectory did not keep)
        color = item.color or palette.HIGHLIGHT
        layer = canvas.copy()
        cv2.arrowedLine(layer, tuple(raster.fixed(tail).tolist()), tuple(raster.fixed(head).tolist()),
                        raster.bgr(color), thickness(unit), cv2.LINE_AA, raster.SHIFT,
                        tipLength=min(0.3, 12.0 * unit / max(np.hypot(*(head - tail)), 1.0)))
        blend(canvas, layer, alpha)
        if item.label:
            self._note(canvas, view, state, item.label, resolve(item.head, state), unit, alpha, item.label_gap,
                       kind="arrow")

    def _mark(self, canvas, view, state, radii, item, unit, alpha):
        labels = item.labels or tuple(str(k + 1) for k in range(len(item.bodies)))
        middle = view.to_pixels(state.positions[list(item.bodies)].mean(axis=0))
        for body, label in zip(item.bodies, labels):
            centre = view.to_pixels(state.positions[body])
            radius = float(view.length(radii[body]))
            away = np.sign(centre[0] - middle[0]) or 1.0   # beside the body, on the side away from the others
            layer = canvas.copy()
            raster.draw_rings(layer, centre[None], [radius + 3.0 * unit], palette.HIGHLIGHT, thickness(unit))
            blend(canvas, layer, alpha)
            placed, image = place_text(state.layout, label, NOTE_PIXELS * unit, centre, "mark",
                                       gap=radius + 4.0 * unit, first=(int(away), -1))   # up, beside the body
            self._label(canvas, placed, image, unit, palette.HIGHLIGHT, alpha)

    def _note(self, canvas, view, state, text, at, unit, alpha, gap=0.0, dot=False, kind="note"):
        """Text beside a world point, `gap` world units away, where the frame's layout finds
        room (to its right, centred on its height, when that is free); with `dot`, the point
        itself is marked."""
        x, y = view.to_pixels(at)
        if dot:
            layer = canvas.copy()
            cv2.circle(layer, (int(round(x)), int(round(y))), max(2, int(round(3 * unit))),
                       raster.bgr(palette.HIGHLIGHT), -1, cv2.LINE_AA)
            blend(canvas, layer, alpha)
        placed, image = place_text(state.layout, text, NOTE_PIXELS * unit, (x, y), kind,
                                   gap=float(view.length(gap)) + 4 * unit)
        self._label(canvas, placed, image, unit, palette.TEXT, alpha)

    def _label(self, canvas, placed, image, unit, color, alpha) -> None:
        """Paste a placed label, with a leader line from its point when it sits far from it."""
        left, top = placed.rect[:2]
        if placed.leader:
            start = np.array(placed.anchor, float)
            end = placing.nearest_point(placed.rect, start)
            layer = canvas.copy()
            raster.draw_lines_px(layer, [start], [end], palette.DIM_TEXT, max(1, int(round(unit))))
            blend(canvas, layer, alpha)
        self.drawn.append((placed.kind, paste(canvas, image, left, top, color, alpha), placed.bound))


def status(canvas, state, text: str, color=None) -> tuple:
    """A status line an overlay writes (what its structure is doing), at a note's size where the
    frame's layout finds room, nearest the top-left corner, clear of the box and the bodies.
    Returns its rectangle."""
    layout = state.layout
    pixels = NOTE_PIXELS * layout.unit
    image = text_image(text, pixels)
    placed = layout.status(image.shape[::-1], "status", text, text_pixels(pixels))
    return paste(canvas, image, placed.rect[0], placed.rect[1], color or palette.TEXT, 1.0)


def place_text(layout, text: str, pixels: float, anchor, kind: str, gap: float = 0.0, first=None) -> tuple:
    """(Placed, coverage) of a label naming `anchor`: on one line where the layout finds room
    for it near its point, else on two lines if that finds room nearer (a long note beside a
    narrow box), else where the one line met the fewest obstacles."""
    image = text_image(text, pixels)
    placed = layout.place(image.shape[::-1], anchor, kind, text, text_pixels(pixels), gap, first)
    halves = split_line(text)
    if (placed.fits and not placed.leader) or halves is None:
        return placed, image
    layout.placed.remove(placed)
    wrapped = two_lines(*halves, pixels)
    again = layout.place(wrapped.shape[::-1], anchor, kind, text, text_pixels(pixels), gap, first)
    if again.fits and (again.leader <= placed.leader or not placed.fits):
        return again, wrapped
    layout.placed.remove(again)
    layout.placed.append(placed)
    return placed, image


def moment(value, state) -> float:
    """A time in seconds, or a function of the frame's state giving one (None: never yet)."""
    if callable(value):
        value = value(state)
    return math.inf if value is None else float(value)


def resolve(point: Point, state) -> np.ndarray:
    """A world point, or a function of the frame's state that gives one."""
    return np.asarray(point(state) if callable(point) else point, dtype=np.float64)


STRIPS_SHARE = 0.4         # caption strips take at most this share of a panel's height


def panel_unit(height: float, room: float = math.inf, lines: int = 0, frame_height: float = BASE_HEIGHT) -> float:
    """The scale of a panel `height` pixels tall in a frame `frame_height` tall: 1 at
    BASE_HEIGHT, not below MIN_UNIT of the frame's own scale (smaller text stops being readable:
    a panel of a 1080p frame is seen at the frame's size), unless its `lines` caption lines would
    then take more than STRIPS_SHARE of the `room` between its title and HUD (a thumbnail-sized
    render)."""
    unit = max(MIN_UNIT * max(frame_height, BASE_HEIGHT) / BASE_HEIGHT, height / BASE_HEIGHT)
    if lines and lines * line_height(unit) > STRIPS_SHARE * room:
        unit = max(STRIPS_SHARE * room / lines / (1.7 * CAPTION_PIXELS), 0.05)
    return unit


def line_height(unit: float) -> float:
    """Height of one caption line in a strip."""
    return math.ceil(1.7 * CAPTION_PIXELS * unit)


def margin(unit: float) -> float:
    return 10.0 * unit


def thickness(unit: float) -> int:
    return max(1, int(round(1.6 * unit)))


def image_figure(make_image: Callable) -> Callable:
    """A Figure's draw that shows the RGB uint8 image `make_image(state)` (made once, at the
    first draw, e.g. a matplotlib chart of that frame), scaled to fit its region, centred."""
    made = []

    def draw(canvas, rect, view, state, unit):
        if not made:
            made.append(np.ascontiguousarray(make_image(state)[:, :, ::-1]))
        image, (x, y, w, h) = made[0], rect
        scale = min(w / image.shape[1], h / image.shape[0])
        size = (max(1, int(image.shape[1] * scale)), max(1, int(image.shape[0] * scale)))
        fitted = cv2.resize(image, size, interpolation=cv2.INTER_AREA)
        left, top = x + (w - size[0]) // 2, y + (h - size[1]) // 2
        canvas[top:top + size[1], left:left + size[0]] = fitted
    return draw


def changed_rect(before, after):
    """The rectangle (x, y, w, h) of the pixels that differ between two BGR images, or None.
    OpenCV's difference and bounding box of its non-zero bytes (a row of w pixels read as 3w
    bytes): comparing in numpy and reducing over the colour axis took most of a 1080p frame's time."""
    height, width = before.shape[:2]
    x, y, w, h = cv2.boundingRect(cv2.absdiff(before, after).reshape(height, width * 3))
    if w == 0:
        return None
    left, right = x // 3, (x + w - 1) // 3
    return (left, y, right - left + 1, h)


def blend(canvas, layer, alpha: float) -> None:
    """canvas <- layer where it differs, weighted by alpha (a fading line or ring)."""
    if alpha >= 1.0:
        np.copyto(canvas, layer)
    else:
        cv2.addWeighted(layer, alpha, canvas, 1.0 - alpha, 0.0, dst=canvas)


def inside(rect: tuple, bound: tuple) -> bool:
    """Is rect (x, y, w, h) within bound (x, y, w, h)?"""
    x, y, w, h = rect
    bx, by, bw, bh = bound
    return x >= bx and y >= by and x + w <= bx + bw and y + h <= by + bh
