"""Each body's shape, as the World keeps it: a circle of its radius, or a convex polygon.

A polygon is given in the body frame; it is checked and wound counter-clockwise
(shapes.convex_polygon), and the body's reference point is moved to the polygon's centroid —
the point a body turns about — so its vertices are kept relative to the centroid and the body's
position is the centroid in the world. For `shapes.box` and `shapes.regular` the centroid is
the origin already and nothing moves.

All polygons' vertices sit in one array, body i's in vertices[start[i]:start[i + 1]] (none for
a circle), so the compiled step walks them without Python objects.
"""
from __future__ import annotations

from collections import namedtuple

import numpy as np

from ..core.geometry.polygon import bounding_radius, polygon_mass_properties
from ..core.kinds import CIRCLE, POLYGON
from ..shapes import convex_polygon

ShapeTable = namedtuple("ShapeTable", ["shapes", "start", "vertices", "areas", "second_moments", "radii",
                                       "offsets", "notes"])
ShapeTable.__doc__ = """shapes (n,) int8 kinds; start (n + 1,) int64 and vertices (V, 2): each polygon's
vertices about its centroid; for polygon bodies, areas (n,), second_moments (n,) (polar, about
the centroid, per unit density) and radii (n,) (the bounding circle's; NaN for circles);
offsets (n, 2): each centroid in its body frame (0 for circles); notes: what was changed for
the user (polygons rewound)."""


def shape_table(polygons, n: int) -> ShapeTable:
    """The shapes of n bodies from World's `polygons` argument: None (all circles) or a sequence
    of n entries, each None (a circle) or vertices (k, 2)."""
    shapes, start = np.full(n, CIRCLE, np.int8), np.zeros(n + 1, np.int64)
    areas, second, radii = np.full(n, np.nan), np.full(n, np.nan), np.full(n, np.nan)
    offsets, pieces, notes = np.zeros((n, 2)), [], []
    if polygons is not None:
        if isinstance(polygons, np.ndarray) and polygons.dtype != object or len(polygons) != n:
            raise ValueError(f"polygons must give each of the {n} bodies None (a circle) or its vertices; "
                             f"got {len(polygons)} entries")
        for i, given in enumerate(polygons):
            if given is None:
                pieces.append(np.empty((0, 2)))
                continue
            vertices, note = convex_polygon(given, f"the polygon of body {i}")
            if note:
                notes.append(note)
            area, centroid, inertia = polygon_mass_properties(vertices)   # density 1: mass = area
            shapes[i], offsets[i] = POLYGON, centroid
            pieces.append(vertices - centroid)
            areas[i], second[i] = area, inertia
            radii[i] = bounding_radius(pieces[-1])
    counts = np.array([len(p) for p in pieces] if pieces else [0] * n, np.int64)
    start[1:] = np.cumsum(counts)
    vertices = np.concatenate(pieces) if pieces else np.empty((0, 2))
    return ShapeTable(shapes, start, np.ascontiguousarray(vertices, np.float64), areas, second, radii, offsets,
                      notes)


def polygons_of(start, vertices) -> list | None:
    """World's `polygons` argument back from a vertex table (n + 1,), (V, 2) (vertices about the
    centroids; a body with none is a circle), or None if every body is a circle."""
    polygons = [vertices[start[i]:start[i + 1]].copy() if start[i + 1] > start[i] else None
                for i in range(len(start) - 1)]
    return polygons if any(p is not None for p in polygons) else None
