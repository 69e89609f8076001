"""Each body's shape, as the World keeps it: a circle of its radius, a convex polygon, or a
capsule (shapes.capsule: its two cap centres (±length/2, 0) are its rows of the vertex table,
its radius kept in capsule_radii, and the body's radius is its bounding circle's, length/2 + r).

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
from ..core.geometry.capsule import capsule_mass_properties
from ..core.kinds import CAPSULE, CIRCLE, POLYGON
from ..shapes import Capsule, convex_polygon

ShapeTable = namedtuple("ShapeTable", ["shapes", "start", "vertices", "areas", "second_moments", "radii",
                                       "offsets", "notes", "capsule_radii"])
ShapeTable.__doc__ = """shapes (n,) int8 kinds; start (n + 1,) int64 and vertices (V, 2): each polygon's
vertices about its centroid; for polygon bodies, areas (n,), second_moments (n,) (polar, about
the centroid, per unit density) and radii (n,) (the bounding circle's; NaN for circles);
offsets (n, 2): each centroid in its body frame (0 for circles); notes: what was changed for
the user (polygons rewound); capsule_radii (n,): each capsule's own radius (NaN for the others)."""


def shape_table(polygons, n: int) -> ShapeTable:
    """The shapes of n bodies from World's `shapes` (or `polygons`) argument: None (all circles)
    or a sequence of n entries, each None (a circle), a shapes.Capsule or vertices (k, 2)."""
    shapes, start = np.full(n, CIRCLE, np.int8), np.zeros(n + 1, np.int64)
    areas, second, radii = np.full(n, np.nan), np.full(n, np.nan), np.full(n, np.nan)
    capsule_radii = np.full(n, np.nan)
    offsets, pieces, notes = np.zeros((n, 2)), [], []
    if polygons is not None:
        if isinstance(polygons, np.ndarray) and polygons.dtype != object or len(polygons) != n:
            raise ValueError(f"shapes must give each of the {n} bodies None (a circle), a capsule or a polygon's "
                             f"vertices; got {len(polygons)} entries")
        for i, given in enumerate(polygons):
            if given is None:
                pieces.append(np.empty((0, 2)))
                continue
            if isinstance(given, Capsule):
                half = 0.5 * given.length
                shapes[i], capsule_radii[i], radii[i] = CAPSULE, given.radius, half + given.radius
                areas[i], second[i] = capsule_mass_properties(given.length, given.radius)
                pieces.append(np.array([[-half, 0.0], [half, 0.0]]))
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
                      notes, capsule_radii)


def polygons_of(start, vertices, capsule_radii=None) -> list | None:
    """World's `shapes` argument back from a vertex table (n + 1,), (V, 2) (vertices about the
    centroids; a body with none is a circle) and capsule_radii (n,) (a capsule where it is a
    number; None: no capsules), or None if every body is a circle."""
    def entry(i):
        if capsule_radii is not None and not np.isnan(capsule_radii[i]):
            return Capsule(2.0 * float(vertices[start[i] + 1, 0]), float(capsule_radii[i]))
        return vertices[start[i]:start[i + 1]].copy() if start[i + 1] > start[i] else None
    polygons = [entry(i) for i in range(len(start) - 1)]
    return polygons if any(p is not None for p in polygons) else None
