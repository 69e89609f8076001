"""The slides' hierarchy of bounding volumes: a candidate pair is tested against its bodies'
bounding circles, then their axis-aligned boxes, then their oriented boxes, then the exact shapes,
and goes on to the next level only while it passes. Each level is tighter and dearer than the one
before: a circle test is one distance, a box test four comparisons, an oriented box test four
projections (separating axes), the exact test a polygon's every edge.

A pair's *level* is how many of the four tests it passes in that order (0: its bounding circles
are apart; 4: the shapes touch). Counted over a state's pairs, counts[l] is how many pairs pass
level l, so counts never rise down the funnel; counts[3] are the pairs that truly touch, and
(counts[l] - counts[3]) / counts[l] is level l's false-positive rate.

The volumes are conservative: every pair whose shapes touch passes every level. A polygon's
volumes are computed from rotated vertices, so each is grown by SLACK of its body's bounding
radius: round-off can then never reject a pair the exact test finds touching (a pair that close
is a false positive only at the scale of SLACK). A circle's bounding circle is the circle itself
(tested exactly, as the exact level does), its box and oriented box the square around it.

The exact level is the narrow phase's own touching tests (narrowphase/circles.py, polygons.py):
touching counts, as depth >= 0 does in the manifolds. The discrete engine reads it from the
manifolds its contact phase finds for the same state (response/rows.py: pair_manifolds), so a
frame's funnel costs no second exact test.

The pairs are those whose bounding circles' boxes overlap. Counted over any larger set of pairs
the counts are the same (a pair whose bounding circles are apart passes no level), so the
discrete engine counts over the candidates its broad phase found for the state's contacts
(boxes grown by the bodies' margins): a state's counts cost a pass over its pairs, no query of
their own (record_levels, once per recorded frame).
"""
from __future__ import annotations

import math

import numpy as np
from numba.core import types
from numba.extending import overload

from ..broadphase import find_pairs
from ..broadphase.step import candidate_pairs
from ..core.compiling import compiled, kernel
from ..core.geometry.polygon import oriented_box, place_polygons, polygon_bounds
from ..core.kinds import CAPSULE, CIRCLE, POLYGON, capsules_flag
from ..model.trajectory import NOT_COUNTED
from ..narrowphase.circles import circles_touch
from ..narrowphase.manifold import shapes_touch

SLACK = 1e-9         # polygons' volumes grown by this share of their bounding radius (see above)
# a body's volumes, one row each: its box, then its oriented box's centre, axis and half extents
XMIN, YMIN, XMAX, YMAX, CX, CY, UX, UY, HALF_W, HALF_H = range(10)


@compiled(error_model="numpy")
def frame_boxes(shapes, body_vertices, vertex_start):
    """Each polygon's oriented box in its body frame (n, 5): centre x, y, half extents, the angle
    of its half-width axis (geometry/polygon.py: oriented_box; zeros for circles). A body's box
    turns with it, so this is found once and only placed at each state (body_volumes). A
    capsule's is its core's (half width half its length, no height)."""
    boxes = np.zeros((shapes.shape[0], 5))
    for i in range(shapes.shape[0]):
        if shapes[i] == POLYGON:
            boxes[i, 0], boxes[i, 1], boxes[i, 2], boxes[i, 3], boxes[i, 4] = oriented_box(
                body_vertices[vertex_start[i]:vertex_start[i + 1]])
        elif shapes[i] == CAPSULE:   # its core along x: body_volumes rounds it by the radius
            boxes[i, 2] = body_vertices[vertex_start[i] + 1, 0]
    return boxes


@compiled(error_model="numpy")
def body_volumes(shapes, positions, angles, radii, boxes, vertex_start, vertices, volumes):
    """Each body's box and oriented box in the world, into volumes (n, 10) (columns above).
    boxes (n, 5): frame_boxes; vertices (V, 2): the polygons' world vertices at these poses
    (place_polygons)."""
    for i in range(positions.shape[0]):
        x, y, r = positions[i, 0], positions[i, 1], radii[i]
        grow = SLACK * r
        if shapes[i] == CIRCLE:
            volumes[i, XMIN], volumes[i, YMIN], volumes[i, XMAX], volumes[i, YMAX] = x - r, y - r, x + r, y + r
            volumes[i, CX], volumes[i, CY], volumes[i, UX], volumes[i, UY] = x, y, 1.0, 0.0
            volumes[i, HALF_W], volumes[i, HALF_H] = r, r
        else:
            s, e = vertex_start[i], vertex_start[i + 1]
            xmin, ymin, xmax, ymax = polygon_bounds(vertices[s:e])
            volumes[i, XMIN], volumes[i, YMIN], volumes[i, XMAX], volumes[i, YMAX] = xmin, ymin, xmax, ymax
            cx, cy, half_w, half_h, turn = boxes[i, 0], boxes[i, 1], boxes[i, 2], boxes[i, 3], boxes[i, 4]
            c, sn = math.cos(angles[i]), math.sin(angles[i])
            volumes[i, CX], volumes[i, CY] = x + c * cx - sn * cy, y + sn * cx + c * cy
            volumes[i, UX], volumes[i, UY] = math.cos(angles[i] + turn), math.sin(angles[i] + turn)
            volumes[i, HALF_W], volumes[i, HALF_H] = half_w, half_h
        if shapes[i] == CAPSULE:
            grow += r - boxes[i, 2]   # its core's box and oriented box, rounded by its own radius
        volumes[i, XMIN] -= grow
        volumes[i, YMIN] -= grow
        volumes[i, XMAX] += grow
        volumes[i, YMAX] += grow
        volumes[i, HALF_W] += grow
        volumes[i, HALF_H] += grow
    return volumes


@kernel
def _circles_overlap(shapes, positions, radii, i, j):
    if shapes[i] == CIRCLE and shapes[j] == CIRCLE:
        return circles_touch(positions, radii, i, j)     # the bounding circles are the shapes
    ri = radii[i] * (1.0 + SLACK) if shapes[i] != CIRCLE else radii[i]
    rj = radii[j] * (1.0 + SLACK) if shapes[j] != CIRCLE else radii[j]
    dx, dy = positions[j, 0] - positions[i, 0], positions[j, 1] - positions[i, 1]
    return dx * dx + dy * dy <= (ri + rj) * (ri + rj)


@kernel
def _boxes_overlap(volumes, i, j):
    return (volumes[i, XMIN] <= volumes[j, XMAX] and volumes[j, XMIN] <= volumes[i, XMAX]
            and volumes[i, YMIN] <= volumes[j, YMAX] and volumes[j, YMIN] <= volumes[i, YMAX])


@kernel
def _reach(volumes, i, lx, ly):
    """Half the width of body i's oriented box along the unit axis (lx, ly)."""
    ux, uy = volumes[i, UX], volumes[i, UY]
    return volumes[i, HALF_W] * abs(ux * lx + uy * ly) + volumes[i, HALF_H] * abs(ux * ly - uy * lx)


@kernel
def _oriented_overlap(volumes, i, j):
    """Separating axes of two rectangles: their four side directions. Touching counts."""
    dx, dy = volumes[j, CX] - volumes[i, CX], volumes[j, CY] - volumes[i, CY]
    for k in range(4):
        body = i if k < 2 else j
        ux, uy = volumes[body, UX], volumes[body, UY]
        lx, ly = (ux, uy) if k % 2 == 0 else (-uy, ux)
        if abs(dx * lx + dy * ly) > _reach(volumes, i, lx, ly) + _reach(volumes, j, lx, ly):
            return False
    return True


@compiled(error_model="numpy")
def passes(level, shapes, positions, radii, vertices, start, volumes, i, j, capsules):
    """Does pair (i, j) pass `level` (an index into LEVELS) on its own? capsules: None for a world
    without capsules, else True (narrowphase/manifold.py: shapes_touch)."""
    if level == 0:
        return _circles_overlap(shapes, positions, radii, i, j)
    if level == 1:
        return _boxes_overlap(volumes, i, j)
    if level == 2:
        return _oriented_overlap(volumes, i, j)
    return shapes_touch(shapes, positions, radii, vertices, start, i, j, capsules)


@kernel
def _volume_level(shapes, positions, radii, volumes, i, j):
    """How many of the three bounding volumes pair (i, j) passes down the funnel, stopping at the
    first it fails. (The same tests as `passes`, written out: a call per level through `passes`
    costs more than the tests themselves.)"""
    if not _circles_overlap(shapes, positions, radii, i, j):
        return 0
    if not _boxes_overlap(volumes, i, j):
        return 1
    if not _oriented_overlap(volumes, i, j):
        return 2
    return 3


@kernel
def _level(shapes, positions, radii, vertices, start, volumes, i, j, capsules):
    """Pair (i, j)'s level: how many tests it passes down the funnel, stopping at the first it
    fails."""
    level = _volume_level(shapes, positions, radii, volumes, i, j)
    if level == 3 and shapes_touch(shapes, positions, radii, vertices, start, i, j, capsules):
        return 4
    return level


@compiled(error_model="numpy")
def pair_levels(shapes, positions, radii, vertices, start, volumes, pairs, levels, capsules):
    """Each pair's level (k,): how many tests it passes down the funnel, stopping at the first
    it fails. Returns levels."""
    for p in range(pairs.shape[0]):
        levels[p] = _level(shapes, positions, radii, vertices, start, volumes, pairs[p, 0], pairs[p, 1], capsules)
    return levels


@compiled(error_model="numpy")
def each_level(shapes, positions, radii, vertices, start, volumes, pairs, out, capsules):
    """Every level tested on its own for each pair: out (k, 4) bool. Returns out."""
    for p in range(pairs.shape[0]):
        for level in range(4):
            out[p, level] = passes(level, shapes, positions, radii, vertices, start, volumes, pairs[p, 0], pairs[p, 1],
                                   capsules)
    return out


def level_scratch(bodies):
    """What record_levels needs, made once a run (a block of a world asleep cost more finding the
    frame_boxes again than stepping): the bodies' frame_boxes and room for their volumes (n, 10);
    None for a world of circles, which is not counted."""
    if not np.any(bodies.shapes != CIRCLE):
        return None
    return frame_boxes(bodies.shapes, bodies.body_vertices, bodies.vertex_start), np.empty((len(bodies.shapes), 10))


def record_levels(scratch, bodies, pairs, vertices, touching, counts):
    """counts (4,) <- how many pairs of the bodies' state pass each level (count_levels), for
    worlds with polygons (compiled code only). scratch is level_scratch's: None for a world of
    circles, which is not counted and does not compile the counting (counts stay NOT_COUNTED):
    every level of a pair of circles is its bounding circle's, so the funnel would only repeat
    the touching pairs, at the cost of a pass over the step's candidates a frame
    (benchmarks/hierarchy.py). pairs: the step's candidate pairs, which include every pair
    count_levels needs; vertices: the polygons' world vertices at this state (placed by the
    narrow phase); touching (k,): whether each pair's shapes touch, as the narrow phase found
    them at this state (response/rows.py: pair_manifolds) — the exact level without a second
    separating-axis test (the polygons pile's funnel: 18 -> 6 us a frame)."""
    raise NotImplementedError("record_levels is called from compiled code")


@overload(record_levels)
def _record_levels(scratch, bodies, pairs, vertices, touching, counts):
    if isinstance(scratch, types.NoneType):
        return lambda scratch, bodies, pairs, vertices, touching, counts: None

    def record(scratch, bodies, pairs, vertices, touching, counts):
        boxes, volumes = scratch
        count_placed(bodies, pairs, vertices, boxes, volumes, touching, counts)
    return record


@compiled(error_model="numpy")
def circle_pairs(bodies, broad):
    """The pairs (k, 2) of the bodies' state (the engine's Bodies) whose bounding circles' boxes
    overlap, from the engine's broad-phase state."""
    b = bodies
    n = b.positions.shape[0]
    lo, hi = np.empty((n, 2)), np.empty((n, 2))
    for i in range(n):
        reach = b.radii[i] * (1.0 + 2.0 * SLACK)
        for axis in range(2):
            lo[i, axis], hi[i, axis] = b.positions[i, axis] - reach, b.positions[i, axis] + reach
    return candidate_pairs(broad, lo, hi) if n >= 2 else np.empty((0, 2), np.intp)


@compiled(error_model="numpy")
def count_levels(bodies, pairs, vertices, counts):
    """counts (4,) <- how many pairs of the bodies' state (the engine's Bodies) pass each level,
    over pairs (k, 2) that include every pair whose bounding circles overlap (circle_pairs, or
    any larger set); vertices: scratch (V, 2) for the polygons' world vertices."""
    b = bodies
    place_polygons(b.body_vertices, b.vertex_start, b.positions, b.angles, vertices)
    touching = np.empty(pairs.shape[0], np.bool_)
    for p in range(pairs.shape[0]):
        touching[p] = shapes_touch(b.shapes, b.positions, b.radii, vertices, b.vertex_start, pairs[p, 0], pairs[p, 1])
    count_placed(b, pairs, vertices, frame_boxes(b.shapes, b.body_vertices, b.vertex_start),
                 np.empty((b.positions.shape[0], 10)), touching, counts)


@kernel
def count_placed(bodies, pairs, vertices, boxes, volumes, touching, counts):
    """count_levels, given the polygons' world vertices (V, 2) at this state, their frame_boxes
    (n, 5), room for their volumes (n, 10), and whether each pair's shapes touch (k,)."""
    b = bodies
    counts[:] = 0
    if b.positions.shape[0] < 2:
        return
    body_volumes(b.shapes, b.positions, b.angles, b.radii, boxes, b.vertex_start, vertices, volumes)
    for p in range(pairs.shape[0]):
        level = _volume_level(b.shapes, b.positions, b.radii, volumes, pairs[p, 0], pairs[p, 1])
        if level == 3 and touching[p]:
            level = 4
        for passed in range(level):
            counts[passed] += 1


# --- for users, tests and overlays --------------------------------------------------------------

def volumes_of(world, positions=None, angles=None) -> tuple:
    """(world vertices (V, 2), volumes (n, 10)) of the world's bodies at these poses (default its
    own): each body's box and oriented box (columns XMIN ... HALF_H)."""
    positions = world.positions if positions is None else np.ascontiguousarray(positions, np.float64)
    angles = world.angles if angles is None else np.ascontiguousarray(angles, np.float64)
    vertices = world.placed_vertices(positions, angles)
    boxes = frame_boxes(world.shapes, world.body_vertices, world.vertex_start)
    volumes = body_volumes(world.shapes, positions, angles, world.radii, boxes, world.vertex_start, vertices,
                           np.empty((world.n, 10)))
    return vertices, volumes


def hierarchy(world, positions=None, angles=None, pairs=None) -> dict:
    """The funnel of a state: pairs (k, 2) (default: every pair whose bounding circles' boxes
    overlap), each pair's level (k,) (how many of LEVELS it passes in order), each level on its
    own `passes` (k, 4) bool (for tests: every touching pair passes every level), and counts (4,):
    the pairs passing each level."""
    positions = world.positions if positions is None else np.ascontiguousarray(positions, np.float64)
    angles = world.angles if angles is None else np.ascontiguousarray(angles, np.float64)
    pairs, levels, args = _levels(world, positions, angles, pairs)
    alone = each_level(*args, pairs, np.empty((len(pairs), 4), np.bool_), capsules_flag(world.shapes))
    return {"pairs": pairs, "levels": levels, "passes": alone, "counts": _counts(levels)}


def _counts(levels) -> np.ndarray:
    """The pairs passing each of the 4 levels (4,) int64, from each pair's level (k,)."""
    return (levels[:, None] > np.arange(4)).sum(axis=0).astype(np.int64)


def _levels(world, positions, angles, pairs) -> tuple:
    """(pairs, each pair's level, the bodies' arrays pair_levels read) of hierarchy()."""
    if pairs is None:
        reach = world.radii[:, None] * (1.0 + 2.0 * SLACK)
        pairs = find_pairs("grid", positions - reach, positions + reach)
    pairs = np.ascontiguousarray(np.asarray(pairs, np.int64).reshape(-1, 2))
    vertices, volumes = volumes_of(world, positions, angles)
    args = (world.shapes, positions, world.radii, vertices, world.vertex_start, volumes)
    return pairs, pair_levels(*args, pairs, np.empty(len(pairs), np.int64), capsules_flag(world.shapes)), args


def world_counts(world) -> np.ndarray:
    """The counts (4,) the discrete engine records for the world's own state (NOT_COUNTED for a
    world of circles, as record_levels): the levels alone, not each level on its own."""
    if world.n == 0 or not (world.shapes != CIRCLE).any():
        return np.full(4, NOT_COUNTED, np.int64)
    return _counts(_levels(world, world.positions, world.angles, None)[1])


def false_positive_rates(counts) -> np.ndarray:
    """Per level, over every frame of counts (F, 4) (Trajectory.hierarchy; frames not counted
    are left out): the share of the pairs passing it whose shapes do not touch (NaN if none
    passed)."""
    counts = np.asarray(counts)
    counts = counts[(counts >= 0).all(axis=1)]
    passed = counts.sum(axis=0).astype(float)
    with np.errstate(invalid="ignore", divide="ignore"):
        return np.where(passed > 0, (passed - passed[3]) / passed, np.nan)
