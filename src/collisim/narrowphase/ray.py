"""A ray against one body, whatever its shape: the exact test the broad phases' ray traversals
call for each body they cannot rule out.

RAY_TESTS maps a shape kind to its test (geometry/ray.py), as SHAPE_PAIRS does for contacts;
`ray_body` is the compiled dispatcher. A new shape kind adds a row and a branch (a polygon's
test would read its vertices from the world's arrays the way the circle reads its radius).
"""
import numpy as np
from numba import njit

from ..core.geometry.ray import ray_circle
from ..core.kinds import CIRCLE

RAY_TESTS = {CIRCLE: ray_circle}


@njit(cache=True, inline="always")
def ray_body(shapes, positions, radii, i, ox, oy, ux, uy):
    """Where the ray o + t·u (u unit) first touches body i: (t, nx, ny, inside), t = inf for a
    miss (see geometry/ray.py). shapes: (n,) kinds; positions: (n, 2); radii: (n,)."""
    if shapes[i] == CIRCLE:
        return ray_circle(ox, oy, ux, uy, positions[i, 0], positions[i, 1], radii[i])
    return np.inf, 0.0, 0.0, False
