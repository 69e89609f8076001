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
from numba import njit


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
    if isinstance(value, bool) or not isinstance(value, (int, np.integer)) or value < minimum:
        raise ValueError(f"{name} must be an integer >= {minimum}; got {value!r}")
    return int(value)


def check_positive_option(name: str, value) -> float:
    """A length option such as cell_size=: a finite number > 0."""
    if isinstance(value, bool) or not isinstance(value, (int, float, np.integer, np.floating)):
        raise ValueError(f"{name} must be a positive number; got {value!r}")
    if not (math.isfinite(value) and value > 0):
        raise ValueError(f"{name} must be a positive finite number; got {value!r}")
    return float(value)


@njit(cache=True)
def boxes_overlap(lo, hi, i, j):
    """Do boxes i and j overlap? lo, hi: (n, 2). Touching (equal edges) counts.

    Written with & rather than `and`: without the short-circuit branches numba
    compiles the hot loops that call this about three times faster.
    """
    return ((lo[i, 0] <= hi[j, 0]) & (lo[j, 0] <= hi[i, 0])
            & (lo[i, 1] <= hi[j, 1]) & (lo[j, 1] <= hi[i, 1]))


@njit(cache=True)
def centre_spread(lo, hi, members, axis):
    """Max minus min of the centres of boxes `members` on `axis`. lo, hi: (n, 2)."""
    low, high = np.inf, -np.inf
    for i in members:
        centre = 0.5 * lo[i, axis] + 0.5 * hi[i, axis]
        low = min(low, centre)
        high = max(high, centre)
    return high - low


@njit(cache=True)
def widest_axis(lo, hi, members):
    """The axis (0 or 1) along which the centres of boxes `members` spread widest
    (ties go to axis 0). lo, hi: (n, 2); members: (m,) indices, m >= 1."""
    return 1 if centre_spread(lo, hi, members, 1) > centre_spread(lo, hi, members, 0) else 0


@njit(cache=True)
def new_pair_buffer(n):
    """An empty (capacity, 2) intp buffer for a kernel to append pairs to."""
    return np.empty((max(16, 2 * n), 2), np.intp)


@njit(cache=True)
def push_pair(pairs, count, i, j):
    """Write the pair {i, j} as (min, max) into row `count` of `pairs`.

    The buffer doubles when full, so kernels need not know the answer's size in
    advance. Returns the (possibly new) buffer and the new count.
    """
    if count == pairs.shape[0]:
        grown = np.empty((2 * count, 2), np.intp)
        grown[:count] = pairs
        pairs = grown
    pairs[count, 0] = min(i, j)
    pairs[count, 1] = max(i, j)
    return pairs, count + 1


@njit(cache=True)
def insertion_sort(values, first, end):
    """Sort values[first:end] in place; quickest for a few elements."""
    for k in range(first + 1, end):
        item = values[k]
        m = k
        while m > first and values[m - 1] > item:
            values[m] = values[m - 1]
            m -= 1
        values[m] = item


@njit(cache=True)
def sorted_unique_pairs(pairs, n):
    """Sort raw pairs with i < j lexicographically and drop repeats.

    pairs: (k, 2) intp with entries in 0 .. n - 1. A counting sort on i groups
    the pairs by their first index in O(n + k); each group's j's (a handful
    per box) are then sorted on their own, and repeats skipped.
    """
    k = pairs.shape[0]
    group_start = np.zeros(n + 1, np.intp)
    for p in range(k):
        group_start[pairs[p, 0] + 1] += 1
    group_start = np.cumsum(group_start)
    cursor = group_start[:-1].copy()
    partners = np.empty(k, np.intp)
    for p in range(k):
        i = pairs[p, 0]
        partners[cursor[i]] = pairs[p, 1]
        cursor[i] += 1
    result = np.empty((k, 2), np.intp)
    count = 0
    for i in range(n):
        first, end = group_start[i], group_start[i + 1]
        if end - first > 32:
            partners[first:end].sort()  # a big box's long list
        else:
            insertion_sort(partners, first, end)  # a handful: no call overhead
        for g in range(first, end):
            if g == first or partners[g] != partners[g - 1]:
                result[count, 0] = i
                result[count, 1] = partners[g]
                count += 1
    return result[:count]


class BroadPhase:
    """One broad-phase method, its options, and what it keeps between frames.

    Call :meth:`pairs` once per frame. Subclasses implement ``_find(lo, hi)``
    (called only for n >= 2 boxes) returning raw pairs with i < j in any order,
    and may add entries to ``self.stats``.
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
