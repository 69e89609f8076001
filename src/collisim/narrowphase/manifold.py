"""Contact manifolds of any two bodies, and of a body and a box wall, as the engine needs them:
including *speculative* points of shapes still apart but closer than a margin.

A manifold is narrowphase/polygons.py's tuple (nx, ny, count, depth0, px0, py0, depth1, px1,
py1): the unit normal from the first body towards the second, and up to two points, each with
its depth (negative: a gap) and its position midway between the two surfaces.

A circle, a wall or a segment apart from a shape by a gap g < margin is brought to touching it
(the circle grown by the margin, the wall's plane moved, the segment moved back by g along the
normal), the manifold taken there, and the gap given back: every depth less by g, every point
moved by g/2 along the normal. For convex shapes this is exact: moving along the axis of least
separation keeps the same closest features. Two polygons get theirs where they are
(polygons.py: speculative_polygons): a vertex over a face from the separating-axis test itself,
corner against corner from the closest points.

A polygon's vertices are sliced out only on the branch that needs them.

Bodies' shapes: shapes (n,) kinds; positions (n, 2); radii (n,) (a polygon's bounding radius);
vertices (V, 2) the polygons' world vertices this step, body i's in vertices[start[i]:start[i+1]].
"""
import numpy as np
from numba.core import types
from numba.extending import overload

from ..core.compiling import compiled, kernel
from ..core.kinds import CAPSULE, CIRCLE, POLYGON
from .capsules import (capsule_pair_manifold, capsule_pair_swept_gap, capsule_pair_touch, capsule_segment_manifold,
                       capsule_wall_manifold)
from .circles import circle_circle, circles_touch
from .polygons import (box_wall_halfplane, placed_polygons_touch, polygon_circle, polygon_circle_touch,
                       polygon_halfplane, polygon_segment, speculative_polygons)
from .sweep import swept_circles, swept_polygon_circle, swept_polygons

NONE = (1.0, 0.0, 0, -np.inf, 0.0, 0.0, 0.0, 0.0, 0.0)
TOUCH = 1e-12   # of the coordinates' size: past any rounding of a shape moved to touch another


@kernel
def _given_back(m, gap):
    """Manifold m taken with the second shape moved `gap` closer, for the shapes where they are."""
    nx, ny, count, d0, px0, py0, d1, px1, py1 = m
    half = 0.5 * gap
    return (nx, ny, count, d0 - gap, px0 + half * nx, py0 + half * ny, d1 - gap, px1 + half * nx,
            py1 + half * ny)


@kernel
def _flipped(m):
    """Manifold m with its two shapes swapped: the normal reversed."""
    nx, ny, count, d0, px0, py0, d1, px1, py1 = m
    return -nx, -ny, count, d0, px0, py0, d1, px1, py1


@kernel
def _circles(positions, radii, i, j, margin):
    nx, ny, depth, _, _ = circle_circle(positions, radii, i, j)
    if depth <= -margin:
        return NONE
    reach = radii[i] - 0.5 * depth   # midway between the two surfaces
    return nx, ny, 1, depth, positions[i, 0] + reach * nx, positions[i, 1] + reach * ny, 0.0, 0.0, 0.0


@kernel
def _polygon_circle(a, cx, cy, r, margin):
    m = polygon_circle(a, cx, cy, r + margin)     # the circle grown by the margin
    if m[2] == 0:
        return NONE
    return _given_back(m, margin)


@kernel
def _polygons(a, b, margin):
    m = speculative_polygons(a, b, margin)   # touching, or closer than the margin: its manifold
    return m if m[2] > 0 else NONE


@kernel
def pair_manifold(shapes, positions, radii, vertices, start, i, j, margin, capsules):
    """The manifold of bodies i and j (normal from i to j), with speculative points up to
    `margin` apart; count 0 if they are farther. capsules: None for a world without capsules
    (which compiles no capsule path), else True."""
    if shapes[i] == CIRCLE and shapes[j] == CIRCLE:
        return _circles(positions, radii, i, j, margin)
    if capsules is not None and (shapes[i] == CAPSULE or shapes[j] == CAPSULE):
        return capsule_pair_manifold(shapes, positions, radii, vertices, start, i, j, margin)
    # from here on, circles and polygons only
    if shapes[j] == CIRCLE:
        return _polygon_circle(vertices[start[i]:start[i + 1]], positions[j, 0], positions[j, 1], radii[j], margin)
    if shapes[i] == CIRCLE:
        return _flipped(_polygon_circle(vertices[start[j]:start[j + 1]], positions[i, 0], positions[i, 1], radii[i],
                                        margin))
    return _polygons(vertices[start[i]:start[i + 1]], vertices[start[j]:start[j + 1]], margin)


@kernel
def pair_swept_gap(shapes, positions, radii, vertices, start, i, j, dx, dy, capsules):
    """The least distance between the shapes of bodies i and j (apart where the step starts) while
    body j moves by (dx, dy) relative to body i, turning neither (narrowphase/sweep.py).
    capsules as for pair_manifold."""
    if shapes[i] == CIRCLE and shapes[j] == CIRCLE:
        return _circles_swept(positions, radii, i, j, dx, dy)
    if capsules is not None and (shapes[i] == CAPSULE or shapes[j] == CAPSULE):
        return capsule_pair_swept_gap(shapes, positions, radii, vertices, start, i, j, dx, dy)
    # from here on, circles and polygons only
    if shapes[j] == CIRCLE:
        return swept_polygon_circle(vertices[start[i]:start[i + 1]], positions[j, 0], positions[j, 1], radii[j],
                                    dx, dy)
    if shapes[i] == CIRCLE:   # the polygon j seen from the circle i: the circle moves by -d
        return swept_polygon_circle(vertices[start[j]:start[j + 1]], positions[i, 0], positions[i, 1], radii[i],
                                    -dx, -dy)
    return swept_polygons(vertices[start[i]:start[i + 1]], vertices[start[j]:start[j + 1]], dx, dy)


@kernel
def _circles_swept(positions, radii, i, j, dx, dy):
    return swept_circles(positions[j, 0] - positions[i, 0], positions[j, 1] - positions[i, 1], dx, dy,
                         radii[i] + radii[j])


@kernel
def shapes_touch(shapes, positions, radii, vertices, start, i, j, capsules):
    """Do the shapes of bodies i and j overlap or touch? (The exact test alone, no manifold.)
    capsules as for pair_manifold."""
    if shapes[i] == CIRCLE and shapes[j] == CIRCLE:
        return circles_touch(positions, radii, i, j)
    if capsules is not None and (shapes[i] == CAPSULE or shapes[j] == CAPSULE):
        return capsule_pair_touch(shapes, positions, radii, vertices, start, i, j)
    # from here on, circles and polygons only
    if shapes[j] == CIRCLE:
        return polygon_circle_touch(vertices[start[i]:start[i + 1]], positions[j, 0], positions[j, 1], radii[j])
    if shapes[i] == CIRCLE:
        return polygon_circle_touch(vertices[start[j]:start[j + 1]], positions[i, 0], positions[i, 1], radii[i])
    return placed_polygons_touch(vertices, start, i, j)   # no slices: they cost more than the test


@kernel
def polygon_wall_manifold(vertices, start, i, box, wall, margin):
    """The manifold of polygon body i and one box wall (normal into the wall), with speculative
    points up to `margin` from it."""
    nx, ny, offset = box_wall_halfplane(box, wall)
    m = polygon_halfplane(vertices[start[i]:start[i + 1]], nx, ny, offset + margin)
    if m[2] == 0:
        return NONE
    return _given_back(m, margin)


@compiled
def polygon_segment_manifold(vertices, start, i, segments, k, margin):
    """The manifold of polygon body i and segment k of segments (m, 4) (normal from the polygon
    toward the segment), with speculative points up to `margin` apart; count 0 if farther.
    The segment is a two-sided polygon of two vertices."""
    a = vertices[start[i]:start[i + 1]]
    x0, y0, x1, y1 = segments[k, 0], segments[k, 1], segments[k, 2], segments[k, 3]
    m = polygon_segment(a, x0, y0, x1, y1)
    gap = -m[3]
    if gap >= margin:
        return NONE
    # Taken where the segment overlaps the polygon by a hair, then moved back: at an exact
    # touch, rounding leaves a long segment's face points a hair outside the polygon's face,
    # and the clipping would keep neither. (Moved in by the whole margin instead, a segment
    # ending inside the margin could turn the normal sideways.) The raised end of a tilted
    # face within the margin is kept, as the walls' half-planes keep it: with the deepest
    # corner alone, a box resting on a segment rocked on it and sank.
    back = gap + TOUCH * (1.0 + max(abs(x0), abs(y0), abs(x1), abs(y1)))
    touching = polygon_segment(a, x0 - back * m[0], y0 - back * m[1], x1 - back * m[0], y1 - back * m[1],
                               max(margin - back, 0.0))
    if touching[2] == 0:
        return NONE
    return _given_back(touching, back)


@kernel
def shape_wall_manifold(shapes, radii, vertices, start, i, box, wall, margin, capsules):
    """The manifold of body i, a polygon or a capsule, and one box wall (normal into the wall);
    none for a circle (the walls bounce circles themselves: engine/statics_paths.py). capsules
    as for pair_manifold."""
    if shapes[i] == POLYGON:
        return polygon_wall_manifold(vertices, start, i, box, wall, margin)
    if capsules is not None and shapes[i] == CAPSULE:
        return capsule_wall_manifold(radii, vertices, start, i, box, wall, margin)
    return NONE


@compiled
def shape_segment_manifold(shapes, radii, vertices, start, i, segments, k, margin, capsules):
    """The manifold of body i, a polygon or a capsule, and segment k (normal from the body
    toward the segment); none for a circle (engine/statics_paths.py holds circles). capsules as
    for pair_manifold."""
    if shapes[i] == POLYGON:
        return polygon_segment_manifold(vertices, start, i, segments, k, margin)
    if capsules is not None and shapes[i] == CAPSULE:
        return capsule_segment_manifold(radii, vertices, start, i, segments, k, margin)
    return NONE


# --- compiled only for worlds with polygons ----------------------------------------------------------
# The engine and contacts() call these with `polygons` (core/kinds.shapes_flag): None for a world
# of circles, True for one with polygons, CAPSULE for one with capsules too. Numba picks the
# implementation by that type when the caller compiles (as engine/statics_paths.py does for
# segments and maps), so a world of circles compiles none of the polygon paths (the separating
# axes, the clipping, the half-planes), and a world without capsules none of the capsules'.

def capsules_of(polygons):
    """The kernels' `capsules` argument for a `polygons` flag: True with capsules, else None."""
    raise NotImplementedError("capsules_of is called from compiled code")


@overload(capsules_of)
def _capsules_of(polygons):
    if isinstance(polygons, types.Integer):
        return lambda polygons: True
    return lambda polygons: None


def body_pair_manifold(polygons, shapes, positions, radii, vertices, start, i, j, margin):
    """pair_manifold; for a world of circles (polygons None), the circles' manifold alone."""
    raise NotImplementedError("body_pair_manifold is called from compiled code")


def body_pair_touch(polygons, shapes, positions, radii, vertices, start, i, j):
    """shapes_touch; for a world of circles (polygons None), circles_touch alone."""
    raise NotImplementedError("body_pair_touch is called from compiled code")


def body_pair_swept_gap(polygons, shapes, positions, radii, vertices, start, i, j, dx, dy):
    """pair_swept_gap; for a world of circles (polygons None), the circles' alone."""
    raise NotImplementedError("body_pair_swept_gap is called from compiled code")


def body_wall_manifold(polygons, shapes, radii, vertices, start, i, box, wall, margin):
    """shape_wall_manifold; no contact for a world of circles (it has no polygon nor capsule)."""
    raise NotImplementedError("body_wall_manifold is called from compiled code")


def body_segment_manifold(polygons, shapes, radii, vertices, start, i, segments, k, margin):
    """shape_segment_manifold; no contact for a world of circles (it has no polygon nor capsule)."""
    raise NotImplementedError("body_segment_manifold is called from compiled code")


@overload(body_pair_manifold)
def _body_pair_manifold(polygons, shapes, positions, radii, vertices, start, i, j, margin):
    if isinstance(polygons, types.NoneType):
        return lambda polygons, shapes, positions, radii, vertices, start, i, j, margin: _circles(
            positions, radii, i, j, margin)
    return lambda polygons, shapes, positions, radii, vertices, start, i, j, margin: pair_manifold(
        shapes, positions, radii, vertices, start, i, j, margin, capsules_of(polygons))


@overload(body_pair_touch)
def _body_pair_touch(polygons, shapes, positions, radii, vertices, start, i, j):
    if isinstance(polygons, types.NoneType):
        return lambda polygons, shapes, positions, radii, vertices, start, i, j: circles_touch(positions, radii, i, j)
    return lambda polygons, shapes, positions, radii, vertices, start, i, j: shapes_touch(
        shapes, positions, radii, vertices, start, i, j, capsules_of(polygons))


@overload(body_pair_swept_gap)
def _body_pair_swept_gap(polygons, shapes, positions, radii, vertices, start, i, j, dx, dy):
    if isinstance(polygons, types.NoneType):
        return lambda polygons, shapes, positions, radii, vertices, start, i, j, dx, dy: _circles_swept(
            positions, radii, i, j, dx, dy)
    return lambda polygons, shapes, positions, radii, vertices, start, i, j, dx, dy: pair_swept_gap(
        shapes, positions, radii, vertices, start, i, j, dx, dy, capsules_of(polygons))


@overload(body_wall_manifold)
def _body_wall_manifold(polygons, shapes, radii, vertices, start, i, box, wall, margin):
    if isinstance(polygons, types.NoneType):
        return lambda polygons, shapes, radii, vertices, start, i, box, wall, margin: NONE
    return lambda polygons, shapes, radii, vertices, start, i, box, wall, margin: shape_wall_manifold(
        shapes, radii, vertices, start, i, box, wall, margin, capsules_of(polygons))


@overload(body_segment_manifold)
def _body_segment_manifold(polygons, shapes, radii, vertices, start, i, segments, k, margin):
    if isinstance(polygons, types.NoneType):
        return lambda polygons, shapes, radii, vertices, start, i, segments, k, margin: NONE
    return lambda polygons, shapes, radii, vertices, start, i, segments, k, margin: shape_segment_manifold(
        shapes, radii, vertices, start, i, segments, k, margin, capsules_of(polygons))
