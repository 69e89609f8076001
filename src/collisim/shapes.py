"""Shapes for users: a box, a regular polygon, a capsule, and the check that turns any list of
vertices into the convex, counter-clockwise (k, 2) array the engine expects (or one clear line
saying why it cannot).

    >>> box(2.0, 1.0)                       # (4, 2), centred on the origin, counter-clockwise
    >>> regular(6, 1.0)                     # a hexagon with one vertex at (1, 0)
    >>> capsule(2.0, 0.5)                   # cap centres (-1, 0) and (1, 0), radius 0.5
    >>> vertices, note = convex_polygon([[0, 0], [0, 1], [1, 0]], name="body 3's polygon")
    >>> note                                # "body 3's polygon wound clockwise; reversed ..."
"""
from __future__ import annotations

import numbers
from collections import namedtuple

import numpy as np

from .core.checks import number

# Below this (relative to the polygon's size) an area or a turn is round-off, not shape.
NEGLIGIBLE = 1e-12


def box(width, height) -> np.ndarray:
    """The rectangle width × height centred on the origin: (4, 2), counter-clockwise from the
    bottom-left corner."""
    w = 0.5 * number("box width", width, positive=True)
    h = 0.5 * number("box height", height, positive=True)
    return np.array([[-w, -h], [w, -h], [w, h], [-w, h]])


class Capsule(namedtuple("Capsule", ["length", "radius"])):
    """Two half-discs of `radius` whose centres lie `length` apart on the body's x axis, joined
    by the rectangle between them (Box2D's capsule; pymunk's Segment((-length/2, 0),
    (length/2, 0), radius)). Its centroid is the body origin, midway between the centres."""
    __slots__ = ()


def capsule(length, radius) -> Capsule:
    """The capsule of cap centres (±length/2, 0) and `radius` (both > 0), for World(shapes=...)."""
    return Capsule(number("capsule length", length, positive=True), number("capsule radius", radius, positive=True))


def regular(k, radius) -> np.ndarray:
    """The regular k-gon with circumradius `radius` centred on the origin: (k, 2),
    counter-clockwise, vertex 0 at angle 0."""
    if isinstance(k, bool) or not isinstance(k, numbers.Integral) or k < 3:
        raise ValueError(f"a regular polygon needs a whole number of sides >= 3, got {k!r}")
    radius = number("regular polygon radius", radius, positive=True)
    angles = 2.0 * np.pi * np.arange(k) / k
    return radius * np.column_stack([np.cos(angles), np.sin(angles)])


def convex_polygon(vertices, name: str = "polygon") -> tuple[np.ndarray, str | None]:
    """A user's polygon checked and made counter-clockwise: (vertices (k, 2) float64, note).

    Repeated vertices (and a closing copy of the first) are dropped and vertices lying on the
    straight line between their neighbours removed. A polygon wound clockwise is reversed
    (keeping vertex 0 first) and `note` says so, for the caller to report once; otherwise note
    is None. Anything else — the wrong shape, NaN or inf, fewer than three distinct vertices,
    no area, a reflex vertex, edges that cross — is a ValueError of one line naming `name`."""
    points, index = _distinct_rows(_rows(vertices, name), name)
    edges = np.roll(points, -1, axis=0) - points
    scale = np.ptp(points, axis=0).max()
    area = 0.5 * np.sum(points[:, 0] * np.roll(points[:, 1], -1) - np.roll(points[:, 0], -1) * points[:, 1])
    if abs(area) <= NEGLIGIBLE * scale * scale:
        # a figure eight has no net area either: tell it from a line by how far off the line it goes
        (ex, ey), rest = points[1] - points[0], points[2:] - points[0]
        off_line = np.abs(ex * rest[:, 1] - ey * rest[:, 0]).max()
        why = "its vertices lie on one line" if off_line <= NEGLIGIBLE * scale * scale else "its edges cross"
        raise ValueError(f"{name} has no area: {why}")
    turns = _turns(edges)                  # turns[i]: at vertex i, from edge i-1 to edge i
    straight = np.abs(turns) <= NEGLIGIBLE * np.hypot(*edges.T) * np.hypot(*np.roll(edges, 1, 0).T)
    backwards = np.flatnonzero(straight & (np.sum(edges * np.roll(edges, 1, 0), axis=1) < 0))
    if backwards.size:
        raise ValueError(f"{name} is not convex: it doubles back on itself at vertex {index[backwards[0]]}")
    wrong_way = np.flatnonzero(~straight & (np.sign(turns) != np.sign(area)))
    if wrong_way.size:
        raise ValueError(f"{name} is not convex: its vertices turn both ways at vertex {index[wrong_way[0]]}")
    points = points[~straight]
    if _winding_turns(np.roll(points, -1, axis=0) - points) > 1:
        raise ValueError(f"{name} is not convex: its edges cross (it winds round more than once)")
    if area > 0:
        return np.ascontiguousarray(points), None
    return np.ascontiguousarray(np.roll(points[::-1], 1, axis=0)), \
        f"{name} wound clockwise; reversed to counter-clockwise"


def _rows(vertices, name: str) -> np.ndarray:
    """vertices as a finite (k, 2) float64 array, or ValueError."""
    try:
        points = np.array(vertices, dtype=np.float64)
    except (TypeError, ValueError):
        raise ValueError(f"{name} must be (x, y) number pairs, got {_short(vertices)}") from None
    if points.ndim != 2 or points.shape[1] != 2:
        raise ValueError(f"{name} must have shape (k, 2), one (x, y) row per vertex, got shape {points.shape}")
    if not np.all(np.isfinite(points)):
        raise ValueError(f"{name} contains NaN or inf")
    return points


def _distinct_rows(points: np.ndarray, name: str) -> tuple[np.ndarray, np.ndarray]:
    """points without repeats of the vertex before them, nor closing copies of the first
    vertex at the end, and each kept vertex's index in the user's list."""
    distinct = len(np.unique(points, axis=0))
    if distinct < 3:
        raise ValueError(f"{name} needs at least three distinct vertices, got {distinct}")
    keep = np.any(points != np.roll(points, 1, axis=0), axis=1)
    keep[0] = True
    closing = np.all(points == points[0], axis=1)
    for i in range(len(points) - 1, 0, -1):       # the trailing run back at vertex 0
        if not closing[i]:
            break
        keep[i] = False
    return points[keep], np.flatnonzero(keep)


def _turns(edges: np.ndarray) -> np.ndarray:
    """The cross product of each edge's predecessor with it: > 0 turns left, < 0 right."""
    before = np.roll(edges, 1, axis=0)
    return before[:, 0] * edges[:, 1] - before[:, 1] * edges[:, 0]


def _winding_turns(edges: np.ndarray) -> int:
    """How many full turns the edge direction makes going round once (1 for a simple polygon)."""
    before = np.roll(edges, 1, axis=0)
    angles = np.arctan2(_turns(edges), np.sum(before * edges, axis=1))
    return int(round(abs(angles.sum()) / (2.0 * np.pi)))


def _short(value) -> str:
    text = repr(value)
    return text if len(text) <= 60 else text[:57] + "..."
