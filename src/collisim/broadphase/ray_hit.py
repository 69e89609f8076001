"""The closest hit a ray search keeps, and the order that decides between equal distances.

A search carries its ray as a `Ray` and its best hit so far as a plain tuple
``(t, inside, kind, index, nx, ny)``: the distance along the unit direction, whether the origin
is inside a solid, what was hit (HIT_KINDS) and which one, and the unit normal facing the ray.
Nothing hit yet is `no_hit()`, t = inf.

Canonical order. Hits compare by t, then a hit inside a solid before one on a surface, then
kind in HIT_KINDS order (body < segment < map < wall), then the smaller index. The broad phases
meet the bodies in different orders; keeping the first hit in this total order makes all of
them, and brute force, return the same hit.

Pruning. A traversal may skip a node, cell or box only if the ray enters it beyond
`search_limit`: the best t plus a slack of a few dozen units in the last place of the
coordinates involved. The exact test's t (a square root) and the slab test's entry time round
differently, so a body whose box the ray enters a hair after the best t may still be hit at
exactly the best t (two coincident bodies), and must be tested for the tie rule to see it.
"""
from collections import namedtuple

import numpy as np

from ..core.compiling import compiled, kernel
from ..narrowphase.ray import ray_body
from ._rays import ray_box_entry

BODY, SEGMENT, MAP, WALL = 0, 1, 2, 3
HIT_KINDS = ("body", "segment", "map", "wall")
SLACK = 64 * np.finfo(np.float64).eps

Ray = namedtuple("Ray", ["ox", "oy", "ux", "uy", "max_distance", "scale", "skip_inside"])
Ray.__doc__ = """The segment o + t·u, t in [0, max_distance], u a unit vector; scale is the size of
the coordinates the search handles (|ox| + |oy| + the largest world coordinate), for the slack;
skip_inside: a body whose solid holds the origin is not hit (the ray looks past it)."""


@kernel
def no_hit():
    """The best hit before anything is hit."""
    return np.inf, False, -1, -1, np.nan, np.nan


@kernel
def closer(a, b):
    """Does hit a come before hit b in the canonical order?"""
    if a[0] != b[0]:
        return a[0] < b[0]
    if a[1] != b[1]:
        return a[1]
    if a[2] != b[2]:
        return a[2] < b[2]
    return a[3] < b[3]


@kernel
def keep_closer(best, t, inside, kind, index, nx, ny, max_distance):
    """The hit (t, inside, kind, index, nx, ny) if it lies within max_distance (closed) and
    comes before best, else best."""
    if t <= max_distance:
        hit = (t, inside, kind, index, nx, ny)
        if closer(hit, best):
            return hit
    return best


@kernel
def search_limit(best, ray):
    """How far along the ray a node, cell or box may still hold a hit that beats best."""
    t = best[0]
    if t == np.inf:
        return ray.max_distance
    return min(ray.max_distance, t + SLACK * (ray.scale + t))


@compiled(inline="always")
def test_body(bodies, i, ray, best):
    """Test body i exactly and keep the closer hit. bodies: (shapes (n,), positions (n, 2),
    radii (n,), vertices (V, 2), start (n + 1,), lo (n, 2), hi (n, 2)): the polygons' world
    vertices (narrowphase/ray.py), and lo and hi the bodies' bounding boxes.

    A body counts as hit only where the ray also meets its box within max_distance, by the
    slab test: a ray grazing a circle where it touches its box (the circle's extreme point)
    can round to a hit in the circle test and to a miss in the slab test, and every broad
    phase reaches a body through slab tests of its own regions. Asking the slab test first
    settles such a ray the same way for all of them, brute force included."""
    shapes, positions, radii, vertices, start, lo, hi = bodies
    if ray_box_entry(ray.ox, ray.oy, ray.ux, ray.uy, ray.max_distance,
                     lo[i, 0], lo[i, 1], hi[i, 0], hi[i, 1]) == np.inf:
        return best
    t, nx, ny, inside = ray_body(shapes, positions, radii, vertices, start, i, ray.ox, ray.oy, ray.ux, ray.uy)
    if inside and ray.skip_inside:
        return best
    return keep_closer(best, t, inside, BODY, i, nx, ny, ray.max_distance)


@kernel
def test_run(bodies, items, first, end, ray, best, tested):
    """test_body for the bodies items[first:end] (a leaf's or a cell's run); returns the best
    hit and `tested` plus the bodies tested."""
    for a in range(first, end):
        best = test_body(bodies, items[a], ray, best)
    return best, tested + (end - first)
