"""Growable arrays for compiled kernels that do not know their output's size in advance
(candidate pairs, contacts, collision logs): double the capacity when full."""
import numpy as np
from numba import njit


@njit(cache=True)
def grown(array, size):
    """`array` if it has at least `size` rows, else a copy with room for max(size, twice as many)."""
    if size <= array.shape[0]:
        return array
    bigger = np.empty((max(size, 2 * array.shape[0]),) + array.shape[1:], array.dtype)
    bigger[:array.shape[0]] = array
    return bigger
