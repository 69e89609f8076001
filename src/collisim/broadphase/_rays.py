"""Rays against boxes: the slab test every broad phase's ``raycast`` uses.

A ray is the segment ``origin + t * u`` for t in [0, max_distance], u the unit
direction. A box is the overlap of two *slabs*: the strip x0 <= x <= x1 and
the strip y0 <= y <= y1. The ray is inside the x strip for the t between the
times it crosses x = x0 and x = x1 (in whichever order its direction meets
them), and likewise for y. It is inside the box while it is inside both
strips and inside [0, max_distance]: it enters at the largest of the three
start times and leaves at the smallest of the end times, and it hits the box
if it enters no later than it leaves. Equal times count: a ray grazing a
corner or running along an edge touches the box, just as touching boxes
overlap in ``pairs``.

A direction component of exactly 0 cannot be divided by: the ray is then
parallel to that strip, and inside it for all t or for none, depending on
whether its origin lies within the strip.

:func:`ray_box_entry` is the only slab test in the package. The traversals
(grid walk, kd-tree, BVH, sweep) only decide which boxes to hand to it, and
they compute their crossing times with the same :func:`crossing`, so their
pruning and this test agree to the last bit.
"""

import math

import numpy as np

from ..core.arrays import grown
from ..core.compiling import compiled, kernel


def check_ray(origin, direction, max_distance) -> tuple[float, float, float, float, float]:
    """(ox, oy, ux, uy, max_distance) with u = direction / |direction|, or ValueError.

    origin, direction: (2,) finite, direction non-zero; max_distance: a
    number >= 0, inf allowed.
    """
    origin = np.asarray(origin, dtype=np.float64)
    direction = np.asarray(direction, dtype=np.float64)
    if origin.shape != (2,) or direction.shape != (2,):
        raise ValueError(f"ray origin and direction must each be two numbers (x, y); "
                         f"got shapes {origin.shape} and {direction.shape}")
    if not np.isfinite(origin).all():
        raise ValueError("ray origin must be finite (no NaN or inf)")
    if not np.isfinite(direction).all():
        raise ValueError("ray direction must be finite (no NaN or inf)")
    dx, dy = float(direction[0]), float(direction[1])
    if dx == 0.0 and dy == 0.0:
        raise ValueError("ray direction must be non-zero")
    try:
        max_distance = float(max_distance)
    except (TypeError, ValueError):
        raise ValueError(f"max_distance must be a number; got {max_distance!r}") from None
    if not max_distance >= 0.0:  # also catches NaN
        raise ValueError(f"max_distance must be >= 0 (inf is allowed); got {max_distance!r}")
    norm = math.hypot(dx, dy)
    if math.isinf(norm):  # components near the float64 limit: halving them is exact
        dx, dy = 0.5 * dx, 0.5 * dy
        norm = math.hypot(dx, dy)
    return float(origin[0]), float(origin[1]), dx / norm, dy / norm, max_distance


@kernel
def crossing(o, u, edge):
    """The t at which o + t * u (one axis, u != 0) reaches the line at `edge`."""
    return (edge - o) / u


@kernel
def clip_to_slab(enter, leave, o, u, edge_lo, edge_hi):
    """Narrow the ray's time interval [enter, leave] to the part inside the
    slab edge_lo <= coordinate <= edge_hi on one axis (o, u: the ray's
    coordinate and direction there). An empty result has enter > leave."""
    if u == 0.0:
        if edge_lo <= o <= edge_hi:
            return enter, leave  # parallel and inside the slab: all the time
        return np.inf, -np.inf  # parallel and outside: never
    t_a, t_b = crossing(o, u, edge_lo), crossing(o, u, edge_hi)
    # max(enter, ...) with enter first: numba's max keeps the first of equal
    # values, so an origin on an edge enters at +0.0 rather than -0.0.
    return max(enter, min(t_a, t_b)), min(leave, max(t_a, t_b))


@kernel
def ray_box_entry(ox, oy, ux, uy, max_distance, x0, y0, x1, y1):
    """Where the ray (ox, oy) + t (ux, uy), t in [0, max_distance], enters the
    box [x0, x1] x [y0, y1]: that t (0 if the origin is in or on the box), or
    inf if it misses. Touching counts as a hit."""
    enter, leave = clip_to_slab(0.0, max_distance, ox, ux, x0, x1)
    enter, leave = clip_to_slab(enter, leave, oy, uy, y0, y1)
    return enter if enter <= leave else np.inf


@compiled
def push_hit(found, t_enter, count, i, t):
    """Append box i entered at t to the buffers found (m,) intp and t_enter (m,)
    float64, growing them when full; returns both buffers and the new count."""
    found = grown(found, count + 1)
    t_enter = grown(t_enter, count + 1)
    found[count] = i
    t_enter[count] = t
    return found, t_enter, count + 1


@compiled
def hits_in_run(lo, hi, boxes, first, end, ox, oy, ux, uy, max_distance, found, t_enter, count):
    """Test the boxes boxes[first:end] (a leaf's or a cell's run) against the ray and append
    the hits (push_hit). Returns found, t_enter and the new count."""
    for a in range(first, end):
        i = boxes[a]
        t = ray_box_entry(ox, oy, ux, uy, max_distance, lo[i, 0], lo[i, 1], hi[i, 0], hi[i, 1])
        if t < np.inf:
            found, t_enter, count = push_hit(found, t_enter, count, i, t)
    return found, t_enter, count


@kernel
def farther_then_nearer(t_left, t_right):
    """The order in which to push two children on a traversal stack so the one the ray
    enters first is searched first: (farther, nearer) as 0 = left, 1 = right, each with
    whether the ray reaches it at all (t < inf)."""
    if t_left <= t_right:
        return 1, t_right < np.inf, 0, t_left < np.inf
    return 0, t_left < np.inf, 1, True


@compiled
def new_hit_buffers():
    """Empty buffers for push_hit: (16,) intp and (16,) float64."""
    return np.empty(16, np.intp), np.empty(16, np.float64)


def sorted_hits(found: np.ndarray, t_enter: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Sort hits (k,) by (t_enter, index) and drop repeats.

    A box met twice (in two grid cells, or two kd-tree leaves) has the same
    t_enter both times, since both came from ray_box_entry with the same
    arguments, so repeats end up side by side.
    """
    order = np.lexsort((found, t_enter))
    found, t_enter = found[order], t_enter[order]
    keep = np.ones(len(found), bool)
    keep[1:] = found[1:] != found[:-1]
    return found[keep].astype(np.intp), t_enter[keep].astype(np.float64)
