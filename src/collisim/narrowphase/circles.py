"""Circle-circle detection: two circles touch when the distance between their centres is at
most the sum of their radii (compared squared, so no square root is needed)."""
import numpy as np
from numba import njit


@njit(cache=True)
def touching_pairs(positions, radii, candidates):
    """Keep the candidate pairs whose circles overlap or touch.

    positions: (n, 2); radii: (n,); candidates: (k, 2) intp -> (m, 2) intp, same order
    """
    keep = np.zeros(candidates.shape[0], dtype=np.bool_)
    for c in range(candidates.shape[0]):
        i, j = candidates[c, 0], candidates[c, 1]
        dx = positions[j, 0] - positions[i, 0]
        dy = positions[j, 1] - positions[i, 1]
        reach = radii[i] + radii[j]
        keep[c] = dx * dx + dy * dy <= reach * reach
    return candidates[keep]
