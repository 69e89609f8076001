"""Small geometric helpers shared by the continuous and the discrete barrier code."""
import math

from numba import njit


@njit(cache=True, error_model="numpy")
def closest_on_segment(px, py, x0, y0, x1, y1):
    """The point of segment (x0, y0)-(x1, y1) closest to (px, py): (qx, qy, u), where
    u in [0, 1] is its fraction along the segment (0 or 1 at an end point)."""
    ex, ey = x1 - x0, y1 - y0
    length2 = ex * ex + ey * ey
    u = 0.0 if length2 == 0.0 else min(max(((px - x0) * ex + (py - y0) * ey) / length2, 0.0), 1.0)
    return x0 + u * ex, y0 + u * ey, u


@njit(cache=True, error_model="numpy")
def contact_normal(px, py, qx, qy, x0, y0, x1, y1):
    """Unit normal (nx, ny, distance) from the point q of a segment towards p. When p
    lies on the segment (distance 0) the segment's own normal is used."""
    dx, dy = px - qx, py - qy
    distance = math.hypot(dx, dy)
    if distance > 0.0:
        return dx / distance, dy / distance, distance
    ex, ey = x1 - x0, y1 - y0
    length = math.hypot(ex, ey)
    if length == 0.0:
        return 1.0, 0.0, 0.0
    return -ey / length, ex / length, 0.0
