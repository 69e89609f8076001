"""A ray against one body, whatever its shape: the exact test the broad phases' ray traversals
call for each body they cannot rule out.

RAY_TESTS maps a shape kind to its test (core/geometry/ray.py), as SHAPE_PAIRS does for
contacts; `ray_body` is the compiled dispatcher. A new shape kind adds a row and a branch.
"""
import numpy as np

from ..core.compiling import compiled
from ..core.geometry.capsule import ray_capsule
from ..core.geometry.ray import ray_circle, ray_polygon
from ..core.kinds import CAPSULE, CIRCLE, POLYGON
from .capsules import ray_capsule_body

RAY_TESTS = {CIRCLE: ray_circle, POLYGON: ray_polygon, CAPSULE: ray_capsule}


@compiled(inline="always")
def ray_body(shapes, positions, radii, vertices, start, i, ox, oy, ux, uy):
    """Where the ray o + t·u (u unit) first touches body i: (t, nx, ny, inside), t = inf for a
    miss (see core/geometry/ray.py). shapes: (n,) kinds; positions: (n, 2); radii: (n,);
    vertices (V, 2): the polygons' vertices (and capsules' cap centres) in the world, body i's vertices[start[i]:start[i + 1]]."""
    if shapes[i] == CIRCLE:
        return ray_circle(ox, oy, ux, uy, positions[i, 0], positions[i, 1], radii[i])
    if shapes[i] == POLYGON:
        return ray_polygon(ox, oy, ux, uy, vertices, start[i], start[i + 1])
    if shapes[i] == CAPSULE:
        return ray_capsule_body(radii, vertices, start, i, ox, oy, ux, uy)
    return np.inf, 0.0, 0.0, False
