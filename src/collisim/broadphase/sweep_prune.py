"""Sweep and prune: sort the boxes along one axis and sweep a line across.

Project every box onto one axis; it becomes an interval [min, max]. Sort the
intervals by their min and walk through them in that order. The video keeps an
*active list* of the intervals the sweep line is still inside: when a new
interval starts, those that ended before its min leave the list, and every one
still in it overlaps the new one on the sweep axis: each is reported as a
candidate pair, as the video reports them (its six particles: 15 pairs narrowed
to those whose intervals meet). The other axis is not looked at; the narrow
phase tests every candidate exactly, so what collides is the same.

The code finds the same pairs from the other end, without the list: box i's
partners on the sweep axis that start after it are exactly the boxes that
follow it in the sorted order up to the first one starting beyond i's max
(the order is sorted by min, so that run is contiguous). Walking forward over
that run costs one comparison per pair that overlaps on the sweep axis and one
to stop, O(n + pairs), where pruning an active list means scanning it whole at
every box (O(n^1.5) for a gas). The coordinates are gathered into sort order
first, so the walk reads memory in sequence. (For a uniform gas the runs still grow
as the square root of n: a sweep line crosses that many boxes.)

We sweep the axis along which the box centres vary most (the larger
variance; the video names it among the refinements): spread-out intervals
keep the runs short. Boxes crowded into one stretch of that axis still give
nearly every pair as a candidate: the bad input the video warns of.

Beyond the video — temporal coherence. From one frame to the next the circles
barely move, so last frame's sorted order is almost sorted already. Insertion
sort repairs an almost-sorted list in nearly linear time, so
:class:`SweepAndPrune` keeps the order between frames and re-sorts from
scratch only when it must (first frame, a different number of boxes, the
sweep axis changed, or the order turned out to be badly scrambled).

Box queries and ray casts use the same sorted order. A box can only meet the
query (or the ray) if its interval on the sweep axis meets the query's (or
the ray's) span along that axis; binary searches in the sorted order find the
run of boxes for which that is possible, and only those are tested.
"""

import math

import numpy as np

from ..core.compiling import compiled, kernel
from ._common import BroadPhase, box_meets_query, check_boxes, new_pair_buffer, push_index, put_pair, reserve_pairs
from ._rays import crossing, new_hit_buffers, push_hit, ray_box_entry


def sweep_axis(lo: np.ndarray, hi: np.ndarray) -> int:
    """The axis (0 or 1) along which the box centres have the larger variance."""
    if len(lo) < 2:
        return 0
    # Column by column (fast for (n, 2) arrays); lo + hi is twice the centre,
    # which scales both variances alike.
    return int(np.var(lo[:, 1] + hi[:, 1]) > np.var(lo[:, 0] + hi[:, 0]))


@compiled
def sweep(lo, hi, order, axis):
    """The pairs whose intervals on `axis` overlap (touching counts): the video's candidates.

    lo, hi: (n, 2) box corners; order: (n,) box indices sorted by lo[:, axis]
    (ties by index); axis: 0 or 1. Returns (k, 2) intp pairs with i < j.
    """
    n = order.shape[0]
    # The intervals in sweep order: the forward walks read them in sequence.
    start, end = np.empty(n), np.empty(n)
    for p in range(n):
        i = order[p]
        start[p], end[p] = lo[i, axis], hi[i, axis]
    pairs, count = new_pair_buffer(n), np.intp(0)
    for p in range(n):
        # The run of later boxes starting at or before this one's end: every one overlaps
        # it on the sweep axis; the first starting beyond it ends the run.
        stop = p + 1
        while stop < n and start[stop] <= end[p]:
            stop += 1
        pairs = reserve_pairs(pairs, count, stop - p - 1)
        for q in range(p + 1, stop):
            count = put_pair(pairs, count, order[p], order[q])
    return pairs[:count]


@kernel
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


@compiled
def sorted_intervals(lo, hi, order, axis):
    """The boxes' intervals on `axis` in sweep order, for binary searches.

    lo, hi: (n, 2); order: (n,) sorted by lo[:, axis]. Returns starts (n,),
    lo[order, axis], ascending, and reach (n,): reach[p] is the largest
    hi[:, axis] among the first p + 1 boxes of the order.

    The starts alone do not say where the boxes that could still overlap
    begin: a long box starting far back may reach past the query. Walking
    back from the query until the boxes get too far away needs the largest
    extent, and "lo + extent >= query" rounds; reach is ascending too, so a
    binary search in it finds the first box from which some earlier-starting
    box (or itself) gets far enough, using only exact comparisons. One giant
    box near the start makes that run long, as it would make the largest
    extent large.
    """
    n = order.shape[0]
    starts = np.empty(n)
    reach = np.empty(n)
    furthest = -np.inf
    for p in range(n):
        i = order[p]
        starts[p] = lo[i, axis]
        furthest = max(furthest, hi[i, axis])
        reach[p] = furthest
    return starts, reach


@compiled
def sweep_query(lo, hi, order, axis, qx0, qy0, qx1, qy1):
    """Boxes overlapping the query box [qx0, qx1] x [qy0, qy1].

    lo, hi: (n, 2); order: (n,) sorted by lo[:, axis]. Returns (found (k,)
    intp, number of boxes tested): only the boxes from the first whose reach
    gets to the query's min to the last starting no later than its max.
    """
    starts, reach = sorted_intervals(lo, hi, order, axis)
    q_min, q_max = (qx0, qx1) if axis == 0 else (qy0, qy1)
    first = np.searchsorted(reach, q_min, side="left")  # earlier boxes all end before q_min
    end = np.searchsorted(starts, q_max, side="right")  # later boxes all start after q_max
    found, count = np.empty(16, np.intp), np.intp(0)
    for p in range(first, end):
        i = order[p]
        if box_meets_query(lo, hi, i, qx0, qy0, qx1, qy1):
            found, count = push_index(found, count, i)
    return found[:count], max(end - first, 0)


@kernel
def first_position(values, o, u, max_distance, within):
    """First p at which the ray reaches values[p] within max_distance
    (within=True) or only beyond it (within=False): crossing(o, u, values[p])
    <= max_distance, or > max_distance. values: (n,); the answer must be
    false up to some p and true from there on. Returns p in 0 .. n."""
    low, high = 0, values.shape[0]
    while low < high:
        mid = (low + high) // 2
        if (crossing(o, u, values[mid]) <= max_distance) == within:
            high = mid
        else:
            low = mid + 1
    return low


@compiled
def sweep_raycast(lo, hi, order, axis, ox, oy, ux, uy, max_distance):
    """Boxes the ray meets, among those whose sweep-axis interval its span crosses.

    lo, hi: (n, 2); order: (n,) sorted by lo[:, axis]. Returns found (k,)
    intp, t_enter (k,) float64 and the number of boxes tested.

    The span is compared in ray time t, with the same crossing() the slab test
    uses, rather than by computing the far end o + max_distance * u (which
    rounds, and could cut off a box the slab test touches at max_distance).
    """
    starts, reach = sorted_intervals(lo, hi, order, axis)
    o, u = (ox, ux) if axis == 0 else (oy, uy)
    if u > 0:  # travelling up the axis: boxes must end at or after o, start within reach
        first = np.searchsorted(reach, o, side="left")
        end = first_position(starts, o, u, max_distance, False)
    elif u < 0:  # travelling down: boxes must start at or before o, end within reach
        first = first_position(reach, o, u, max_distance, True)
        end = np.searchsorted(starts, o, side="right")
    else:  # across the sweep axis: boxes must contain o on it
        first = np.searchsorted(reach, o, side="left")
        end = np.searchsorted(starts, o, side="right")
    (found, t_enter), count = new_hit_buffers(), np.intp(0)
    for p in range(first, end):
        i = order[p]
        t = ray_box_entry(ox, oy, ux, uy, max_distance, lo[i, 0], lo[i, 1], hi[i, 0], hi[i, 1])
        if t < np.inf:
            found, t_enter, count = push_hit(found, t_enter, count, i, t)
    return found[:count], t_enter[:count], max(end - first, 0)


class SweepAndPrune(BroadPhase):
    """Sweep and prune that keeps its sorted order from frame to frame."""

    name = "sweep_prune"

    def __init__(self):
        super().__init__()
        self._order = np.empty(0, np.intp)
        self._axis = -1

    def _find(self, lo: np.ndarray, hi: np.ndarray) -> np.ndarray:
        axis = self._sort(lo, hi)
        return sweep(lo, hi, self._order, axis)

    def _query(self, lo, hi, qx0, qy0, qx1, qy1):
        axis = self._sort(lo, hi)
        found, tested = sweep_query(lo, hi, self._order, axis, qx0, qy0, qx1, qy1)
        return found, tested, tested

    def _raycast(self, lo, hi, ox, oy, ux, uy, max_distance):
        axis = self._sort(lo, hi)
        found, t_enter, tested = sweep_raycast(lo, hi, self._order, axis,
                                               ox, oy, ux, uy, max_distance)
        return found, t_enter, tested, tested

    def _sort(self, lo: np.ndarray, hi: np.ndarray) -> int:
        """Bring self._order up to date (repaired, or sorted afresh); the sweep axis."""
        axis = sweep_axis(lo, hi)
        keys = np.ascontiguousarray(lo[:, axis])
        shifts = self._repair(keys, axis)
        if shifts < 0:
            self._order = np.argsort(keys, kind="stable")
            self._axis = axis
        self.stats.update(axis=axis, resorted=shifts < 0, shifts=max(shifts, 0))
        return axis

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
