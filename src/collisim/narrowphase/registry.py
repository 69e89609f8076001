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


def contacts(world, positions=None) -> dict:
    """The contacts between the bodies of `world` (at `positions`, default the world's own):
    pairs (k, 2) with i < j, normals (k, 2) from i to j, depths (k,), points (k, 2)."""
    from ..broadphase import find_pairs
    positions = world.positions if positions is None else np.asarray(positions, np.float64)
    reach = world.radii[:, None]
    pairs = touching_pairs(world.shapes, positions, world.radii,
                           find_pairs("grid", positions - reach, positions + reach))
    rows = contact_rows(world.shapes, positions, world.radii, pairs)
    return {"pairs": pairs, "normals": rows[:, :2], "depths": rows[:, 2], "points": rows[:, 3:]}
