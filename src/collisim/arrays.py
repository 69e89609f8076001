"""Growable arrays for compiled kernels that do not know their output's size in advance
(candidate pairs, contacts, collision logs): double the capacity when full."""
import numpy as np
from numba import njit


@njit(cache=True)
def grown(array, size, used=-1):
    """`array` if it has at least `size` rows, else a copy with room for max(size, twice as many).
    Only the first `used` rows are copied (default: all), so a buffer that reserves far more than
    it has filled (a collision log making room for an event per body and wall in every step)
    keeps only what it holds in memory: the pages of the new array past them are never touched."""
    if size <= array.shape[0]:
        return array
    bigger = np.empty((max(size, 2 * array.shape[0]),) + array.shape[1:], array.dtype)
    kept = array.shape[0] if used < 0 else used
    bigger[:kept] = array[:kept]
    return bigger
