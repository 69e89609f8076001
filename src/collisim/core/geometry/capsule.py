"""A capsule's area and second moment, and a ray against it: the capsule of cap centres a and
b and radius r is every point within r of the segment ab (its core).

Mass properties as Box2D v3's b2ComputeCapsuleMass: the rectangle |ab| × 2r plus the two
half-discs, each moved from its own centroid (4r/3π from its flat side) to the body centre by
the parallel-axis theorem.
"""
import math

import numpy as np

from ..compiling import kernel
from .ray import facing_perpendicular, nonnegative, ray_circle


def capsule_mass_properties(length: float, radius: float) -> tuple[float, float]:
    """(area, polar second moment about the centre) of the capsule of cap centres
    (±length/2, 0) and `radius`, per unit density (mass = area)."""
    rr, half = radius * radius, 0.5 * length
    box_area, disc_area = 2.0 * radius * length, math.pi * rr
    box_second = box_area * (length * length + 4.0 * rr) / 12.0
    # the two half-discs about their own centroids (a full disc's ½·r² minus the offset²), then
    # moved out to the centre: ½r² - c² + (h + c)² = ½r² + h² + 2hc, c = 4r/3π
    lever = 4.0 * radius / (3.0 * math.pi)
    disc_second = disc_area * (0.5 * rr + half * half + 2.0 * half * lever)
    return box_area + disc_area, box_second + disc_second


@kernel
def ray_capsule(ox, oy, ux, uy, ax, ay, bx, by, r):
    """Where the ray o + t·u meets the capsule of core a-b and radius r: (t, nx, ny, inside),
    as core/geometry/ray.py's tests. The outline is the two cap circles and the two sides (the
    core moved out by r either way); the first of their hits is the capsule's (a hit of a cap
    circle inside the rectangle lies beyond a side's hit, so it never wins wrongly)."""
    ex, ey = bx - ax, by - ay
    length = math.hypot(ex, ey)
    tx, ty = ex / length, ey / length          # along the core
    px, py = -ty, tx                           # its left side's outward normal
    along = (ox - ax) * tx + (oy - ay) * ty
    side = (ox - ax) * px + (oy - ay) * py
    if abs(side) < r and 0.0 <= along <= length:
        return 0.0, 0.0, 0.0, True             # inside the rectangle
    best, nx, ny, inside = ray_circle(ox, oy, ux, uy, ax, ay, r)
    if inside:
        return best, nx, ny, inside
    t, cx, cy, inside = ray_circle(ox, oy, ux, uy, bx, by, r)
    if inside:
        return t, cx, cy, inside
    if t < best:
        best, nx, ny = t, cx, cy
    approach = px * ux + py * uy
    for sign in (1.0, -1.0):                   # the side facing the ray: crossed from outside
        room = sign * side - r                 # how far outside this side's line the origin is
        rate = sign * approach
        if room >= 0.0 and rate < 0.0:
            t = nonnegative(room / -rate)
            s = along + t * (tx * ux + ty * uy)
            if 0.0 <= s <= length and t < best:
                best, nx, ny = t, sign * px, sign * py
    if best == np.inf:
        return np.inf, 0.0, 0.0, False
    nx, ny = facing_perpendicular(nx, ny, ux, uy)
    return best, nx, ny, False


def capsule_outline(a, b, radius: float, per_cap: int = 32) -> np.ndarray:
    """The capsule of cap centres a, b (2,) and `radius` as a convex counter-clockwise polygon
    (2·per_cap + 2, 2) for drawing: each cap's half circle sampled from one side to the other."""
    a, b = np.asarray(a, np.float64), np.asarray(b, np.float64)
    heading = math.atan2(b[1] - a[1], b[0] - a[0])
    turn = np.linspace(-0.5 * np.pi, 0.5 * np.pi, per_cap + 1) + heading     # b's cap, right side to left
    cap_b = b + radius * np.column_stack([np.cos(turn), np.sin(turn)])
    cap_a = a + radius * np.column_stack([np.cos(turn + np.pi), np.sin(turn + np.pi)])
    return np.concatenate([cap_b, cap_a])
