"""Brute force: test every pair.

With n objects there are n (n - 1) / 2 pairs, so the work grows with n².
That is fine for a few hundred circles and hopeless for a hundred thousand,
but it is the yardstick every cleverer method is checked against: whatever
they report must include every pair this loop finds.

Box queries and ray casts work the same way: test every box. That costs n
per question, however small the query box or short the ray.
"""

import numpy as np

from ..core.compiling import compiled
from ._common import BroadPhase, boxes_overlap, box_meets_query, new_pair_buffer, push_index, put_pair, reserve_pairs
from ._rays import new_hit_buffers, push_hit, ray_box_entry


@compiled
def brute_force_pairs(lo, hi):
    """All overlapping box pairs (i < j). lo, hi: (n, 2) -> (k, 2) intp."""
    n = lo.shape[0]
    pairs, count = new_pair_buffer(n), np.intp(0)
    for i in range(n):
        pairs = reserve_pairs(pairs, count, n - i - 1)   # room for all of i's, outside the loop
        for j in range(i + 1, n):
            if boxes_overlap(lo, hi, i, j):
                count = put_pair(pairs, count, i, j)
    return pairs[:count]


@compiled
def brute_force_query(lo, hi, qx0, qy0, qx1, qy1):
    """Boxes overlapping [qx0, qx1] x [qy0, qy1], ascending. lo, hi: (n, 2) -> (k,) intp."""
    found, count = np.empty(16, np.intp), np.intp(0)
    for i in range(lo.shape[0]):
        if box_meets_query(lo, hi, i, qx0, qy0, qx1, qy1):
            found, count = push_index(found, count, i)
    return found[:count]


@compiled
def brute_force_raycast(lo, hi, ox, oy, ux, uy, max_distance):
    """Boxes the ray meets, by testing each. lo, hi: (n, 2) -> found (k,) intp,
    t_enter (k,) float64, in index order."""
    (found, t_enter), count = new_hit_buffers(), np.intp(0)
    for i in range(lo.shape[0]):
        t = ray_box_entry(ox, oy, ux, uy, max_distance, lo[i, 0], lo[i, 1], hi[i, 0], hi[i, 1])
        if t < np.inf:
            found, t_enter, count = push_hit(found, t_enter, count, i, t)
    return found[:count], t_enter[:count]


class BruteForce(BroadPhase):
    """Every pair of boxes, tested one by one."""

    name = "brute"

    def _find(self, lo: np.ndarray, hi: np.ndarray) -> np.ndarray:
        return brute_force_pairs(lo, hi)

    def _query(self, lo, hi, qx0, qy0, qx1, qy1):
        n = len(lo)
        return brute_force_query(lo, hi, qx0, qy0, qx1, qy1), n, n

    def _raycast(self, lo, hi, ox, oy, ux, uy, max_distance):
        n = len(lo)
        return (*brute_force_raycast(lo, hi, ox, oy, ux, uy, max_distance), n, n)
