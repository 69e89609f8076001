"""Brute force: test every pair.

With n objects there are n (n - 1) / 2 pairs, so the work grows with n².
That is fine for a few hundred circles and hopeless for a hundred thousand,
but it is the yardstick every cleverer method is checked against: whatever
they report must include every pair this loop finds.
"""

import numpy as np
from numba import njit

from ._common import BroadPhase, boxes_overlap, new_pair_buffer, push_pair


@njit(cache=True)
def brute_force_pairs(lo, hi):
    """All overlapping box pairs (i < j). lo, hi: (n, 2) -> (k, 2) intp."""
    n = lo.shape[0]
    pairs, count = new_pair_buffer(n), 0
    for i in range(n):
        for j in range(i + 1, n):
            if boxes_overlap(lo, hi, i, j):
                pairs, count = push_pair(pairs, count, i, j)
    return pairs[:count]


class BruteForce(BroadPhase):
    """Every pair of boxes, tested one by one."""

    name = "brute"

    def _find(self, lo: np.ndarray, hi: np.ndarray) -> np.ndarray:
        return brute_force_pairs(lo, hi)
