"""The table from a pair of shape kinds to the functions that test and describe their contact.

Box2D keeps such a table (`s_registers[shapeA][shapeB]` in contact.c); here it is a dict for
readers, tests and tools, and two compiled dispatchers, `touching` and `contact`, that the
engine calls per candidate pair. Adding a shape kind means: its functions in a module of this
package, a row in SHAPE_PAIRS (and STATIC_PAIRS), and a branch in each dispatcher (a test checks
that every row of the table is dispatched).

A contact is (nx, ny, depth, px, py): the unit normal from the first body towards the second,
the overlap depth (negative when apart) and the contact point.
"""
import numpy as np
from numba import njit

from ..model.kinds import CIRCLE
from .circles import circle_circle, circles_touch
from .manifold import pair_manifold
from .statics import circle_segment

SHAPE_PAIRS = {(CIRCLE, CIRCLE): (circles_touch, circle_circle)}
STATIC_PAIRS = {(CIRCLE, "segment"): circle_segment}


@njit(cache=True)
def touching(shapes, positions, radii, i, j):
    """Do bodies i and j touch? shapes: (n,) kinds; positions: (n, 2); radii: (n,)."""
    if shapes[i] == CIRCLE and shapes[j] == CIRCLE:
        return circles_touch(positions, radii, i, j)
    return False


@njit(cache=True)
def contact(shapes, positions, radii, i, j):
    """The contact (nx, ny, depth, px, py) of bodies i and j."""
    if shapes[i] == CIRCLE and shapes[j] == CIRCLE:
        return circle_circle(positions, radii, i, j)
    return 1.0, 0.0, -np.inf, positions[i, 0], positions[i, 1]


@njit(cache=True)
def touching_pairs(shapes, positions, radii, candidates):
    """The candidate pairs (k, 2) whose bodies touch, in the same order: (m, 2)."""
    keep = np.zeros(candidates.shape[0], dtype=np.bool_)
    for c in range(candidates.shape[0]):
        keep[c] = touching(shapes, positions, radii, candidates[c, 0], candidates[c, 1])
    return candidates[keep]


@njit(cache=True)
def contact_rows(shapes, positions, radii, pairs):
    """The contacts (k, 5) of pairs (k, 2): rows nx, ny, depth, px, py."""
    rows = np.empty((pairs.shape[0], 5))
    for c in range(pairs.shape[0]):
        rows[c, 0], rows[c, 1], rows[c, 2], rows[c, 3], rows[c, 4] = contact(shapes, positions, radii,
                                                                             pairs[c, 0], pairs[c, 1])
    return rows


@njit(cache=True)
def contact_table(shapes, positions, radii, vertices, start, candidates):
    """One row (i, j, nx, ny, depth, px, py) per contact point of the candidate pairs (k, 2)."""
    most = 1
    for i in range(start.shape[0] - 1):
        most = max(most, start[i + 1] - start[i])
    moved = np.empty((most, 2))
    table = np.empty((2 * candidates.shape[0], 7))
    count = 0
    for c in range(candidates.shape[0]):
        i, j = candidates[c, 0], candidates[c, 1]
        m = pair_manifold(shapes, positions, radii, vertices, start, i, j, 0.0, moved)
        for k in range(m[2]):
            depth, px, py = (m[3], m[4], m[5]) if k == 0 else (m[6], m[7], m[8])
            table[count, 0], table[count, 1], table[count, 2], table[count, 3] = i, j, m[0], m[1]
            table[count, 4], table[count, 5], table[count, 6] = depth, px, py
            count += 1
    return table[:count]


def contacts(world, positions=None) -> dict:
    """The contacts between the bodies of `world` (at `positions`, default the world's own), one
    per contact point (a face on a face has two): pairs (k, 2) with i < j, normals (k, 2) from i
    to j, depths (k,) (>= 0), points (k, 2) midway between the surfaces."""
    from ..broadphase import find_pairs
    from ..geometry.polygon import world_vertices
    positions = world.positions if positions is None else np.asarray(positions, np.float64)
    reach = world.radii[:, None]
    candidates = find_pairs("grid", positions - reach, positions + reach)
    vertices = np.empty_like(world.body_vertices)
    for i in np.flatnonzero(world.shapes != CIRCLE):
        s, e = world.vertex_start[i], world.vertex_start[i + 1]
        world_vertices(world.body_vertices[s:e], positions[i, 0], positions[i, 1], world.angles[i], vertices[s:e])
    table = contact_table(world.shapes, positions, world.radii, vertices, world.vertex_start, candidates)
    return {"pairs": table[:, :2].astype(np.int64), "normals": table[:, 2:4], "depths": table[:, 4],
            "points": table[:, 5:]}
