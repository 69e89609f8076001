"""The table from a pair of shape kinds to the functions that test and describe their contact.

Box2D keeps such a table (`s_registers[shapeA][shapeB]` in contact.c); here it is a dict for
readers, tests and tools, and compiled dispatchers: `touching` and `contact` for pairs of circles
(a test checks that every row of the table is dispatched), and narrowphase/manifold.py's
`pair_manifold`, which the engine calls per candidate pair for every pair of shapes (circles and
convex polygons, with speculative points), and `contact_table` (queries/contacts.py) uses too (both through
`body_pair_manifold`, so a world of circles compiles no polygon path).

A contact is (nx, ny, depth, px, py): the unit normal from the first body towards the second,
the overlap depth (negative when apart) and the contact point.
"""
import numpy as np

from ..core.compiling import compiled, kernel
from ..core.kinds import CAPSULE, CIRCLE, POLYGON
from .capsules import capsule_capsule, capsule_circle, capsule_halfplane, rounded_cores
from .circles import circle_circle, circles_touch
from .manifold import body_pair_manifold, polygon_segment_manifold, polygon_wall_manifold
from .polygons import polygon_circle, speculative_polygons
from .statics import circle_segment

SHAPE_PAIRS = {(CIRCLE, CIRCLE): (circles_touch, circle_circle)}
STATIC_PAIRS = {(CIRCLE, "segment"): circle_segment}
# [kind][kind] -> the function that makes their manifold, for readers and tests: what
# manifold.pair_manifold dispatches to (its first kind is the row's; the other order is the
# same function with the normal flipped). A capsule is a core rounded by its radius
# (narrowphase/capsules.py), so every pair with a capsule is one of two functions.
PAIR_MANIFOLDS = {
    (CIRCLE, CIRCLE): circle_circle,
    (POLYGON, CIRCLE): polygon_circle, (POLYGON, POLYGON): speculative_polygons,
    (CAPSULE, CIRCLE): capsule_circle, (POLYGON, CAPSULE): rounded_cores, (CAPSULE, CAPSULE): capsule_capsule,
}
# a kind against the box walls and the thin segments (response/rows.py: wall_manifolds and
# segment_manifolds; circles meet both in engine/statics_paths.py)
STATIC_MANIFOLDS = {
    (POLYGON, "wall"): polygon_wall_manifold, (POLYGON, "segment"): polygon_segment_manifold,
    (CAPSULE, "wall"): capsule_halfplane, (CAPSULE, "segment"): capsule_capsule,
}


@kernel
def touching(shapes, positions, radii, i, j):
    """Do bodies i and j touch? shapes: (n,) kinds; positions: (n, 2); radii: (n,)."""
    if shapes[i] == CIRCLE and shapes[j] == CIRCLE:
        return circles_touch(positions, radii, i, j)
    return False


@kernel
def contact(shapes, positions, radii, i, j):
    """The contact (nx, ny, depth, px, py) of bodies i and j."""
    if shapes[i] == CIRCLE and shapes[j] == CIRCLE:
        return circle_circle(positions, radii, i, j)
    return 1.0, 0.0, -np.inf, positions[i, 0], positions[i, 1]


@compiled
def contact_table(shapes, positions, radii, vertices, start, candidates, polygons):
    """One row (i, j, nx, ny, depth, px, py) per contact point of the candidate pairs (k, 2).
    polygons: core/kinds.shapes_flag of the world (a world compiles the paths of its own kinds)."""
    table = np.empty((2 * candidates.shape[0], 7))
    count = 0
    for c in range(candidates.shape[0]):
        i, j = candidates[c, 0], candidates[c, 1]
        m = body_pair_manifold(polygons, shapes, positions, radii, vertices, start, i, j, 0.0)
        for k in range(m[2]):
            depth, px, py = (m[3], m[4], m[5]) if k == 0 else (m[6], m[7], m[8])
            table[count, 0], table[count, 1], table[count, 2], table[count, 3] = i, j, m[0], m[1]
            table[count, 4], table[count, 5], table[count, 6] = depth, px, py
            count += 1
    return table[:count]
