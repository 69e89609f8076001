"""Ready-made explainer items for a teacher, as PhET's Collision Lab shows them: velocity and
momentum arrows per body, the centre of mass, a readout of momentum and kinetic energy before
and after a collision, and a "more data" table of each body's mass, position, velocity and
momentum. One line each in a scene file:

    Explainer([*velocity_arrows(world), *momentum_arrows(world), centre_of_mass(world),
               momentum_energy(world), data_table(world)], side=0.3)

Everything is read off the frame's sample (positions, velocities, the events so far) and the
World's masses: nothing is simulated. Their labels are placed by the frame's layout.
"""
from __future__ import annotations

import math

import cv2
import numpy as np

from .. import palette
from ..core.kinds import PAIR
from . import explain, raster
from .items import Arrow, Caption, Figure, Note
from .layout import CAP_SHARE, HERSHEY_CAP

MOMENTUM_COLOR = (240, 150, 90)


def _bodies(world, bodies) -> list:
    return list(range(world.n)) if bodies is None else [int(b) for b in bodies]


def velocity_arrows(world, bodies=None, seconds: float = 0.5, start=0.0, end=math.inf) -> list:
    """An arrow per body from its centre to where it would be `seconds` later: its length is
    |v| * seconds (world units), labelled v1, v2, ..."""
    return [Arrow(_at(b), _ahead(b, seconds, 1.0), start, end, label=f"$v_{{{k + 1}}}$")
            for k, b in enumerate(_bodies(world, bodies))]


def momentum_arrows(world, bodies=None, per_unit: float = 0.25, start=0.0, end=math.inf) -> list:
    """An arrow per body of its momentum m v, `per_unit` world units long per unit of momentum,
    labelled p1, p2, ..."""
    return [Arrow(_at(b), _ahead(b, per_unit, float(world.masses[b])), start, end, label=f"$p_{{{k + 1}}}$",
                  color=MOMENTUM_COLOR) for k, b in enumerate(_bodies(world, bodies))]


def _at(body: int):
    return lambda state: state.positions[body]


def _ahead(body: int, scale: float, mass: float):
    return lambda state: state.positions[body] + scale * mass * state.velocities[body]


def centre_of_mass(world, start=0.0, end=math.inf) -> Note:
    """A dot at the centre of mass, sum m x / sum m, named beside it."""
    masses = np.asarray(world.masses, float)
    return Note("centre of mass", lambda state: masses @ state.positions / masses.sum(), start, end)


def totals(world, state) -> tuple:
    """(momentum (2,), kinetic energy) of the sample: sum m v, sum m |v|^2 / 2."""
    masses = np.asarray(world.masses, float)
    velocities = state.velocities
    return masses @ velocities, 0.5 * float(masses @ np.einsum("ij,ij->i", velocities, velocities))


def readout(world, state) -> dict:
    """The totals now, and around the latest pair collision: "before" as they were at the last
    frame read before the engine logged it, "after" at the first frame read after it (kept in
    state.memory, so they stay while the bodies move on). Call it at every frame shown."""
    memory = state.memory.setdefault("teach readout", {"seen": 0, "last": None, "before": None, "after": None})
    now = totals(world, state)
    collisions = int(np.count_nonzero(state.events.kind == PAIR))
    if collisions > memory["seen"]:
        memory["seen"], memory["before"], memory["after"] = collisions, memory["last"] or now, now
    memory["last"] = now
    return {"now": now, "before": memory["before"], "after": memory["after"]}


def momentum_energy(world, strip: str = "bottom", line: int = 0, start=0.0, end=math.inf) -> Caption:
    """A caption line: total momentum and kinetic energy now, and before -> after the latest
    collision between bodies once there has been one."""
    def text(state):
        found = readout(world, state)
        if found["before"] is None:
            (px, py), energy = found["now"]
            return f"momentum $\\Sigma\\, m v$ = ({number(px)}, {number(py)}),  kinetic energy = {number(energy)}"
        (bx, by), before = found["before"]
        (ax, ay), after = found["after"]
        return (f"collision: momentum ({number(bx)}, {number(by)}) $\\to$ ({number(ax)}, {number(ay)}),  "
                f"kinetic energy {number(before)} $\\to$ {number(after)}")
    return Caption(text, start, end, strip, line)


def number(value: float) -> str:
    """Two decimals, never "-0.00"."""
    text = f"{value:.2f}"
    return "0.00" if text == "-0.00" else text


def table_rows(world, state, bodies=None) -> list:
    """The "more data" table, cells by row: a header and, per body, its mass, position,
    velocity and momentum."""
    rows = [["body", "m", "x", "y", "vx", "vy", "px", "py"]]
    for b in _bodies(world, bodies):
        m, (x, y), (vx, vy) = float(world.masses[b]), state.positions[b], state.velocities[b]
        rows.append([str(b + 1)] + [number(v) for v in (m, x, y, vx, vy, m * vx, m * vy)])
    return rows


def text_width(text: str, scale: float) -> int:
    return cv2.getTextSize(text, cv2.FONT_HERSHEY_SIMPLEX, scale, 1)[0][0]


def data_table(world, bodies=None, place: str = "side", start=0.0, end=math.inf) -> Figure:
    """A Figure of the "more data" table, in the side column (Explainer(side=...)) or a strip.
    Drawn in OpenCV's font: its numbers change every frame, and typesetting them would too."""
    def draw(canvas, rect, view, state, unit):
        x, y, w, h = rect
        rows, pad = table_rows(world, state, bodies), explain.margin(unit)
        least = explain.placing.min_text_pixels(canvas.shape[0]) * CAP_SHARE / HERSHEY_CAP
        scale = max(least, 0.45 * unit)
        # columns right-aligned, as wide as their widest cell ("-10.00" at least) and a space
        widths = [max(text_width(cell, scale) for cell in list(column) + ["-10.00"]) + text_width("  ", scale)
                  for column in zip(*rows)]
        wanted = scale
        scale = max(least, min(scale, scale * (w - 2 * pad) / sum(widths)))   # narrower to fit its column
        widths = [width * scale / wanted for width in widths]
        shown = max(1, int(np.searchsorted(np.cumsum(widths), w - 2 * pad, side="right")))
        rows, widths = [row[:shown] for row in rows], widths[:shown]   # at the smallest text, the last columns go
        step = 1.8 * HERSHEY_CAP * scale
        for k, row in enumerate(rows):
            base = y + pad + (k + 1) * step
            ends = x + pad + np.cumsum(widths)
            for cell, end in zip(row, ends):
                raster.draw_text(canvas, cell, (end, base), scale=scale, anchor="right",
                                 color_rgb=palette.TEXT if k else palette.DIM_TEXT)
            if state.layout is not None:
                state.layout.keep("table", " ".join(row), (x + pad, base - HERSHEY_CAP * scale, ends[-1] - x - pad,
                                  HERSHEY_CAP * scale), scale * HERSHEY_CAP / CAP_SHARE,
                                  (0, 0, canvas.shape[1], canvas.shape[0]))
    return Figure(draw, start, end, place)
