"""Plumbing shared by the broad-phase methods.

* checking the boxes and options a caller passes in,
* the growable pair buffer the numba kernels append candidate pairs to,
* turning a kernel's raw pairs into the contract every method honours:
  a (k, 2) ``np.intp`` array of pairs ``i < j``, sorted and unique,
* :class:`BroadPhase`, the small stateful base class the engine calls once per
  frame.
"""

import math

import numpy as np

from ..core.arrays import grown, heap_sort
from ..core.checks import is_whole
from ..core.compiling import compiled, kernel
from ._rays import check_ray, sorted_hits


def empty_pairs() -> np.ndarray:
    """The answer when there is nothing to pair: shape (0, 2), dtype intp."""
    return np.empty((0, 2), np.intp)


def check_boxes(lo, hi) -> tuple[np.ndarray, np.ndarray]:
    """Return lo, hi as C-contiguous float64 (n, 2) arrays, or raise ValueError.

    Keeping one dtype and layout means each numba kernel compiles exactly once.
    """
    lo = np.ascontiguousarray(lo, dtype=np.float64)
    hi = np.ascontiguousarray(hi, dtype=np.float64)
    if lo.ndim != 2 or lo.shape[1] != 2 or lo.shape != hi.shape:
        raise ValueError(f"lo and hi must both have shape (n, 2); got {lo.shape} and {hi.shape}")
    if not (np.isfinite(lo).all() and np.isfinite(hi).all()):
        raise ValueError("lo and hi must be finite (no NaN or inf)")
    if not (lo <= hi).all():
        raise ValueError("every box needs lo <= hi on both axes")
    if len(lo):
        corner_lo, corner_hi = bounding_box(lo, hi)
        if not np.isfinite(corner_hi - corner_lo).all():
            raise ValueError("box coordinates are too large: their spread overflows float64")
    return lo, hi


def bounding_box(lo: np.ndarray, hi: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Min and max corners, each (2,), of the box around all n >= 1 boxes.

    Reduces column by column: numpy's axis=0 reduction of an (n, 2) array is
    some fifty times slower.
    """
    return (np.array([lo[:, 0].min(), lo[:, 1].min()]),
            np.array([hi[:, 0].max(), hi[:, 1].max()]))


def check_int_option(name: str, value, minimum: int) -> int:
    """An integer option such as leaf_size=, at least `minimum`."""
    if not is_whole(value, minimum):
        raise ValueError(f"{name} must be an integer >= {minimum}; got {value!r}")
    return int(value)


def check_positive_option(name: str, value) -> float:
    """A length option such as cell_size=: a finite number > 0."""
    if isinstance(value, bool) or not isinstance(value, (int, float, np.integer, np.floating)):
        raise ValueError(f"{name} must be a positive number; got {value!r}")
    if not (math.isfinite(value) and value > 0):
        raise ValueError(f"{name} must be a positive finite number; got {value!r}")
    return float(value)


@kernel
def boxes_overlap(lo, hi, i, j):
    """Do boxes i and j overlap? lo, hi: (n, 2). Touching (equal edges) counts.

    Written with & rather than `and`: without the short-circuit branches numba
    compiles the hot loops that call this about three times faster.
    """
    return ((lo[i, 0] <= hi[j, 0]) & (lo[j, 0] <= hi[i, 0])
            & (lo[i, 1] <= hi[j, 1]) & (lo[j, 1] <= hi[i, 1]))


@compiled
def gathered_boxes(lo, hi):
    """The boxes as rows x0, y0, x1, y1 (n, 4): the trees keep a run of these beside their
    index runs and move them together, so a node's passes read memory in sequence rather
    than jump through lo and hi by index (cache misses dominated the build at 10^5 boxes)."""
    rows = np.empty((lo.shape[0], 4))
    for i in range(lo.shape[0]):
        rows[i, 0], rows[i, 1], rows[i, 2], rows[i, 3] = lo[i, 0], lo[i, 1], hi[i, 0], hi[i, 1]
    return rows


@kernel
def copy_row(source, k, target, to):
    """target[to] = source[k] for (m, 4) box rows, as four scalar moves (numba's row
    assignment goes through its general broadcasting path, several times slower)."""
    for c in range(4):
        target[to, c] = source[k, c]


@kernel
def row_centre(rows, k, axis):
    """The centre on `axis` of box row k of gathered_boxes rows."""
    return 0.5 * rows[k, axis] + 0.5 * rows[k, axis + 2]


@kernel
def centre_spread(rows, axis):
    """Max minus min of the centres of box rows (m, 4) (gathered_boxes) on `axis`."""
    low, high = np.inf, -np.inf
    for k in range(rows.shape[0]):
        centre = row_centre(rows, k, axis)
        low = min(low, centre)
        high = max(high, centre)
    return high - low


@kernel
def widest_axis(rows):
    """The axis (0 or 1) along which the centres of box rows (m, 4), m >= 1, (gathered_boxes)
    spread widest (ties go to axis 0)."""
    return 1 if centre_spread(rows, 1) > centre_spread(rows, 0) else 0


@kernel
def select_smallest(values, end, k):
    """Reorder values[:end] in place so values[k] is what a sort would put there, the k
    values before it no larger and those after no smaller (C++'s nth_element), 0 <= k < end.

    Quickselect with a median-of-three pivot and a three-way partition (runs of equal
    values, common in a lattice, cost one pass); after 2 log2(end) rounds without
    converging it sorts what is left, so no input costs more than O(end log end).
    """
    first, last = 0, end - 1
    rounds = 2 * int(np.log2(end + 1)) + 2
    while last - first > 16:
        if rounds == 0:
            heap_sort(values, first, last + 1)
            return
        rounds -= 1
        a, b, c = values[first], values[(first + last) // 2], values[last]
        pivot = max(min(a, b), min(max(a, b), c))
        # Three-way partition: [first, below) < pivot, [below, above] == pivot, (above, last] > pivot.
        below, scan, above = first, first, last
        while scan <= above:
            value = values[scan]
            if value < pivot:
                values[scan], values[below] = values[below], value
                below += 1
                scan += 1
            elif value > pivot:
                values[scan], values[above] = values[above], value
                above -= 1
            else:
                scan += 1
        if k < below:
            last = below - 1
        elif k > above:
            first = above + 1
        else:
            return
    insertion_sort(values, first, last + 1)


@compiled
def new_pair_buffer(n):
    """An empty (capacity, 2) intp buffer for a kernel to append pairs to.

    Kernels start their count at np.intp(0), not 0: numba types a bare 0 as Literal[int](0)
    on the first pass through a loop and then compiles push_pair (and grown below it) a
    second time for that type, about two seconds more on a first run.
    """
    return np.empty((max(16, 2 * n), 2), np.intp)


@compiled
def push_pair(pairs, count, i, j):
    """Write the pair {i, j} as (min, max) into row `count` of `pairs`.

    The buffer doubles when full, so kernels need not know the answer's size in
    advance. Returns the (possibly new) buffer and the new count.
    """
    pairs = grown(pairs, count + 1)
    pairs[count, 0] = min(i, j)
    pairs[count, 1] = max(i, j)
    return pairs, count + 1


@compiled
def reserve_pairs(pairs, count, more):
    """`pairs` with room for `more` pairs after its first `count` (grown as push_pair grows it).

    For a kernel's innermost loop: reassigning the buffer there (push_pair) makes numba count
    references to it on every pass, about 20 ns a pass, ten times the box test. Reserved before
    the loop, the loop only writes (put_pair).
    """
    return grown(pairs, count + more)


@kernel
def put_pair(pairs, count, i, j):
    """Write the pair {i, j} as (min, max) into row `count` of `pairs`, which has room for it
    (reserve_pairs). Returns the new count."""
    pairs[count, 0] = min(i, j)
    pairs[count, 1] = max(i, j)
    return count + 1


@kernel
def insertion_sort(values, first, end):
    """Sort values[first:end] in place; quickest for a few elements."""
    for k in range(first + 1, end):
        item = values[k]
        m = k
        while m > first and values[m - 1] > item:
            values[m] = values[m - 1]
            m -= 1
        values[m] = item


def sorted_unique_pairs(pairs: np.ndarray, n: int) -> np.ndarray:
    """Raw pairs (k, 2) with i < j, entries in 0 .. n - 1, sorted lexicographically and without
    repeats. With numpy rather than a compiled kernel: the scene check on every run (the grid's
    pairs) then compiles nothing beyond what the step compiles anyway (about 3 s on a first run)."""
    keys = pairs[:, 0].astype(np.intp) * n + pairs[:, 1]   # (i, j) order is key order: j < n
    keys.sort()
    keys = keys[np.concatenate(([True], keys[1:] != keys[:-1]))[:len(keys)]]
    result = np.empty((len(keys), 2), np.intp)
    result[:, 0] = keys // n
    result[:, 1] = keys - result[:, 0] * n
    return result


class BroadPhase:
    """One broad-phase method, its options, and what it keeps between frames.

    Three questions, each answered in the method's own way:
    * :meth:`pairs` (once per frame): which boxes may overlap? Subclasses implement
      ``_find(lo, hi)`` (called only for n >= 2 boxes) returning raw pairs with i < j in
      any order, and may add entries to ``self.stats``;
    * :meth:`query`: which boxes overlap this box? (a selection rectangle, an explosion's
      reach, the boxes near a point);
    * :meth:`raycast`: which boxes does this ray segment pass through, and where does it
      enter each? (line of sight, picking, a bullet).
    Subclasses implement, for n >= 1 boxes,
    ``_query(lo, hi, qx0, qy0, qx1, qy1) -> (found (k,) intp, visited, tested)`` and
    ``_raycast(lo, hi, ox, oy, ux, uy, max_distance) -> (found (k,) intp, t_enter (k,)
    float64, visited, tested)``, in any order, repeats allowed. Like ``pairs``, both rebuild
    the structure from lo, hi on every call; afterwards ``self.stats`` holds ``visited`` (how
    many nodes, cells or boxes the method examined: what its structure saved), ``tested``
    (how many boxes it tested exactly) and ``found``.
    """

    name = ""
    OPTIONS: tuple[str, ...] = ()
    EMPTY_STATS: dict = {}  # what stats holds (besides candidates) for n < 2 boxes

    def __init__(self):
        self.stats = {"candidates": 0}

    def pairs(self, lo, hi) -> np.ndarray:
        """Candidate pairs for boxes lo, hi: (n, 2) -> (k, 2) intp, i < j, sorted, unique.

        Every pair of overlapping (or touching) boxes is included.
        """
        lo, hi = check_boxes(lo, hi)
        self.stats = {"candidates": 0, **self.EMPTY_STATS}
        if len(lo) < 2:
            return empty_pairs()
        pairs = sorted_unique_pairs(self._find(lo, hi), len(lo))
        self.stats["candidates"] = len(pairs)
        return pairs

    def describe(self, lo, hi) -> dict:
        """The method's structure for a tutorial picture; here just the pairs."""
        return {"pairs": self.pairs(lo, hi)}

    def _find(self, lo: np.ndarray, hi: np.ndarray) -> np.ndarray:
        raise NotImplementedError


# ------------------------------------------------ box queries (query())

    def query(self, lo, hi, box_lo, box_hi) -> np.ndarray:
        """Indices (k,) intp, ascending and unique, of the boxes lo, hi: (n, 2)
        that overlap the box box_lo, box_hi: (2,) each. Touching counts."""
        lo, hi = check_boxes(lo, hi)
        query_box = check_query_box(box_lo, box_hi)
        self.stats = {"visited": 0, "tested": 0, "found": 0}
        if len(lo) == 0:
            return np.empty(0, np.intp)
        found, visited, tested = self._query(lo, hi, *query_box)
        found = np.unique(found).astype(np.intp)  # a box may sit in several cells or leaves
        self.stats.update(visited=int(visited), tested=int(tested), found=len(found))
        return found

    def raycast(self, lo, hi, origin, direction, max_distance) -> tuple[np.ndarray, np.ndarray]:
        """The boxes lo, hi: (n, 2) that the segment origin + t * u, t in
        [0, max_distance], meets, u = direction / |direction|.

        origin, direction: (2,); max_distance >= 0, may be inf. Returns
        indices (k,) intp and t_enter (k,) float64, the distance along u at
        which the ray enters each box (0 if it starts inside or on it), sorted
        by (t_enter, index). Raises ValueError for a zero or non-finite
        direction, a non-finite origin, or a negative or NaN max_distance.
        """
        lo, hi = check_boxes(lo, hi)
        ray = check_ray(origin, direction, max_distance)
        self.stats = {"visited": 0, "tested": 0, "found": 0}
        if len(lo) == 0:
            return np.empty(0, np.intp), np.empty(0, np.float64)
        found, t_enter, visited, tested = self._raycast(lo, hi, *ray)
        found, t_enter = sorted_hits(found, t_enter)
        self.stats.update(visited=int(visited), tested=int(tested), found=len(found))
        return found, t_enter

    def _query(self, lo, hi, qx0, qy0, qx1, qy1):
        raise NotImplementedError

    def _raycast(self, lo, hi, ox, oy, ux, uy, max_distance):
        raise NotImplementedError


def check_query_box(box_lo, box_hi) -> tuple[float, float, float, float]:
    """The query box's corners as (x0, y0, x1, y1) floats, or raise ValueError.

    box_lo, box_hi: (2,) min and max corners, finite, box_lo <= box_hi.
    """
    box_lo = np.asarray(box_lo, dtype=np.float64)
    box_hi = np.asarray(box_hi, dtype=np.float64)
    if box_lo.shape != (2,) or box_hi.shape != (2,):
        raise ValueError(f"box_lo and box_hi must each be two numbers (x, y); "
                         f"got shapes {box_lo.shape} and {box_hi.shape}")
    if not (np.isfinite(box_lo).all() and np.isfinite(box_hi).all()):
        raise ValueError("the query box corners must be finite (no NaN or inf)")
    if not (box_lo <= box_hi).all():
        raise ValueError("the query box needs box_lo <= box_hi on both axes")
    return float(box_lo[0]), float(box_lo[1]), float(box_hi[0]), float(box_hi[1])


@kernel
def box_meets_query(lo, hi, i, qx0, qy0, qx1, qy1):
    """Does box i (lo, hi: (n, 2)) overlap the box [qx0, qx1] x [qy0, qy1]?
    Touching counts, as in boxes_overlap."""
    return (lo[i, 0] <= qx1) & (qx0 <= hi[i, 0]) & (lo[i, 1] <= qy1) & (qy0 <= hi[i, 1])


@compiled
def overlapping_in_run(lo, hi, boxes, first, end, qx0, qy0, qx1, qy1, found, count):
    """Append the boxes of boxes[first:end] (a leaf's or a cell's run) that overlap the query
    box to found (push_index). Returns found and the new count."""
    for a in range(first, end):
        if box_meets_query(lo, hi, boxes[a], qx0, qy0, qx1, qy1):
            found, count = push_index(found, count, boxes[a])
    return found, count


@compiled
def push_index(found, count, i):
    """Write box index i into slot `count` of `found` (growing it if full);
    returns the (possibly new) buffer and the new count."""
    found = grown(found, count + 1)
    found[count] = i
    return found, count + 1
