"""Sweep and prune: sort the boxes along one axis and sweep a line across.

Project every box onto one axis; it becomes an interval [min, max]. Sort the
intervals by their min and walk through them in that order, keeping an
*active list* of the intervals the sweep line is still inside:

* when a new interval starts, every active interval whose max is smaller than
  the new min has ended — and since all later intervals start even further
  along, it can never overlap anything again, so it leaves the active list;
* every interval still active overlaps the new one on the sweep axis. Those
  that also overlap it on the other axis are reported as a pair;
* the new interval joins the active list.

We sweep the axis along which the box centres vary most (the larger
variance): spread-out intervals keep the active list short.

Beyond the video — temporal coherence. From one frame to the next the circles
barely move, so last frame's sorted order is almost sorted already. Insertion
sort repairs an almost-sorted list in nearly linear time, so
:class:`SweepAndPrune` keeps the order between frames and re-sorts from
scratch only when it must (first frame, a different number of boxes, the
sweep axis changed, or the order turned out to be badly scrambled).
"""

import math

import numpy as np
from numba import njit

from ._common import BroadPhase, check_boxes, new_pair_buffer, push_pair


def sweep_axis(lo: np.ndarray, hi: np.ndarray) -> int:
    """The axis (0 or 1) along which the box centres have the larger variance."""
    if len(lo) < 2:
        return 0
    # Column by column (fast for (n, 2) arrays); lo + hi is twice the centre,
    # which scales both variances alike.
    return int(np.var(lo[:, 1] + hi[:, 1]) > np.var(lo[:, 0] + hi[:, 0]))


@njit(cache=True)
def sweep(lo, hi, order, axis):
    """Overlapping box pairs found by sweeping `axis`.

    lo, hi: (n, 2) box corners; order: (n,) box indices sorted by lo[:, axis]
    (ties by index); axis: 0 or 1. Returns (k, 2) intp pairs with i < j.
    """
    n = lo.shape[0]
    other = 1 - axis
    active = np.empty(n, np.intp)
    n_active = 0
    pairs, count = new_pair_buffer(n), 0
    for i in order:
        # Prune: intervals that ended before this one starts leave for good.
        # (Touching, max == min, still overlaps, so it stays.)
        kept = 0
        for a in range(n_active):
            j = active[a]
            if hi[j, axis] >= lo[i, axis]:
                active[kept] = j
                kept += 1
        n_active = kept
        # Every remaining interval overlaps this one on the sweep axis;
        # report those that overlap on the other axis as well.
        for a in range(n_active):
            j = active[a]
            if lo[i, other] <= hi[j, other] and lo[j, other] <= hi[i, other]:
                pairs, count = push_pair(pairs, count, i, j)
        active[n_active] = i
        n_active += 1
    return pairs[:count]


@njit(cache=True)
def repair_order(keys, order, max_shifts):
    """Insertion-sort `order` in place by (keys[i], i).

    keys: (n,) float64 sort keys; order: (n,) intp permutation from last frame.
    Each element slides left past the elements that should come after it; if
    the order is nearly sorted that is only a few shifts in total. Gives up
    (returns -1, leaving `order` a valid but unsorted permutation) once more
    than `max_shifts` shifts were needed; otherwise returns the shift count.
    """
    shifts = 0
    for k in range(1, order.shape[0]):
        item = order[k]
        m = k
        while m > 0 and (keys[item] < keys[order[m - 1]]
                         or (keys[item] == keys[order[m - 1]] and item < order[m - 1])):
            order[m] = order[m - 1]
            m -= 1
            shifts += 1
        order[m] = item
        if shifts > max_shifts:
            return -1
    return shifts


class SweepAndPrune(BroadPhase):
    """Sweep and prune that keeps its sorted order from frame to frame."""

    name = "sweep_prune"

    def __init__(self):
        super().__init__()
        self._order = np.empty(0, np.intp)
        self._axis = -1

    def _find(self, lo: np.ndarray, hi: np.ndarray) -> np.ndarray:
        axis = sweep_axis(lo, hi)
        keys = np.ascontiguousarray(lo[:, axis])
        shifts = self._repair(keys, axis)
        if shifts < 0:
            self._order = np.argsort(keys, kind="stable")
            self._axis = axis
        self.stats.update(axis=axis, resorted=shifts < 0, shifts=max(shifts, 0))
        return sweep(lo, hi, self._order, axis)

    def _repair(self, keys: np.ndarray, axis: int) -> int:
        """Insertion-sort last frame's order; -1 if it has to be sorted afresh."""
        n = len(keys)
        if axis != self._axis or len(self._order) != n:
            return -1
        # Past about n log2 n shifts a fresh O(n log n) sort is cheaper.
        return repair_order(keys, self._order, n * math.ceil(math.log2(n)))

    def describe(self, lo, hi) -> dict:
        """Sweep axis, sorted order, each box's interval on that axis (row i is
        box i), the active list after each box is processed, and the pairs."""
        lo, hi = check_boxes(lo, hi)
        axis = sweep_axis(lo, hi)
        order = np.argsort(lo[:, axis], kind="stable")
        # After processing the k-th box of the sweep, the active list holds the
        # boxes processed so far whose interval reaches the current min.
        active_steps = [[int(j) for j in order[:k + 1] if hi[j, axis] >= lo[i, axis]]
                        for k, i in enumerate(order)]
        return {
            "axis": axis,
            "order": order,
            "intervals": np.stack((lo[:, axis], hi[:, axis]), axis=1),
            "active_steps": active_steps,
            "pairs": self.pairs(lo, hi),
        }
