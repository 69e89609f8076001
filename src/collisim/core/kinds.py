"""The words every path shares, each defined once: the kinds of shape and of collision event.

Shape kinds index the narrow phase's table of contact functions (narrowphase/registry.py).
Event kinds label every collision (and every resting support, SUPPORT) in a Trajectory, whichever
method found it; the event-driven method's queue numbers its bookkeeping events after the three
kinds it predicts, WALL, PAIR and SEGMENT (engine/ccd/eventqueue.py).
"""
import numpy as np

# numpy integers, not Python ints: numba types a global Python int as its literal value, and a
# kernel handed one compiles a copy per value (append(log, t, PAIR, ...) and append(log, t, WALL,
# ...) would be two compiles of one function); a numpy integer is typed int64 whatever its value.
CIRCLE, POLYGON = np.int64(0), np.int64(1)
# Two half-discs joined by a rectangle (shapes.capsule; Box2D's capsule, pymunk's Segment with a
# radius): its two cap centres are its "vertices" in the vertex table, its radii entry the
# bounding circle's (narrowphase/capsules.py).
CAPSULE = np.int64(2)


def shapes_flag(shapes):
    """What the compiled paths are chosen by (narrowphase/manifold.py): None for a world of
    circles alone, True for one with polygons and no capsule, CAPSULE for one with capsules.
    numba types the three None, bool and int64, so a world compiles the paths of its own kinds."""
    if not np.any(shapes != CIRCLE):
        return None
    return CAPSULE if capsules_flag(shapes) else True


def capsules_flag(shapes):
    """The `capsules` argument of narrowphase/manifold.py's kernels, for calls from Python: True
    for a world with capsules, else None (which compiles no capsule path)."""
    return True if np.any(shapes == CAPSULE) else None

WALL, PAIR, SEGMENT = np.int64(0), np.int64(1), np.int64(2)
# A collision with the collision map (statics/collision_map.py). Its `j` is the map segment
# under ccd, which collides with the map's exact contour chains, and -1 under the discrete
# method, which samples the map's distance field. The per-frame counts add these to the
# segment collisions: both are level geometry.
MAP = np.int64(3)
# Not a collision: the push of a wall or segment that carries a body at rest (its weight), so
# that a wall's pressure includes what it holds (analysis/metrics.py: wall_pressure). Logged at
# least once a frame while the body rests; never counted with the collisions, never flashed.
# Its `j` is the support: a wall side (< N_WALLS), or N_WALLS + the segment (under ccd the
# collision map's chains are numbered after the scene's segments).
SUPPORT = np.int64(4)

# A wall event's `j`: which side of the box (2·axis + side), in this order.
WALL_SIDES = ("left", "right", "bottom", "top")
N_WALLS = len(WALL_SIDES)
