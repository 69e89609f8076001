"""Arrays for compiled kernels: growable ones for outputs whose size is not known in advance
(candidate pairs, contacts, collision logs: double the capacity when full), a row copy, and the
one sort the kernels use."""
import numpy as np

from .compiling import compiled


@compiled
def grown(array, size, used=-1):
    """`array` if it has at least `size` rows, else a copy with room for max(size, twice as many).
    Only the first `used` rows are copied (default: all), so a buffer that reserves far more than
    it has filled (a collision log making room for an event per body and wall in every step)
    keeps only what it holds in memory: the pages of the new array past them are never touched."""
    if size <= array.shape[0]:
        return array
    bigger = np.empty((max(size, 2 * array.shape[0]),) + array.shape[1:], array.dtype)
    copy_rows(array, bigger, array.shape[0] if used < 0 else used)
    return bigger


@compiled
def copy_rows(source, target, count):
    """target[:count] = source[:count], for C-contiguous arrays whose rows have the same shape,
    as a plain loop: numba compiles a slice assignment with the message it raises when the shapes
    differ, and that message's string formatting was 3.5 s of a first run's compiling."""
    width = source.size // source.shape[0] if source.shape[0] > 0 else 0
    flat_source, flat_target = source.reshape(source.size), target.reshape(target.size)
    for k in range(count * width):
        flat_target[k] = flat_source[k]


@compiled
def stable_order(keys):
    """The indices (k,) int64 that put keys (k,) in ascending order, equal keys in the order
    given: np.argsort(keys, kind="stable") for keys without NaN, as a bottom-up merge sort. The
    kernels sort with this one function: numba's own argsort compiles a sort of its own for
    every kind and key type asked of it (its quicksort and its mergesort cost a first frame 1 to
    2 s of compiling)."""
    n = keys.shape[0]
    order, merged = np.arange(n), np.empty(n, np.int64)
    width = 1
    while width < n:
        for start in range(0, n, 2 * width):
            middle, end = min(start + width, n), min(start + 2 * width, n)
            left, right = start, middle
            for out in range(start, end):
                # the left run's key first when equal: the sort is stable
                if right >= end or (left < middle and not keys[order[right]] < keys[order[left]]):
                    merged[out] = order[left]
                    left += 1
                else:
                    merged[out] = order[right]
                    right += 1
        order, merged = merged, order
        width *= 2
    return order
