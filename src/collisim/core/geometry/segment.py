"""A circle against a thin segment: the closest point, and the contact normal and distance.

A segment (x0, y0, x1, y1) has no thickness and round end caps: the circle touches it when its
centre is within its radius of the segment's closest point q. The normal points from q to the
centre (at an end point this is what makes the cap round).
"""
import math

from ..compiling import kernel


@kernel
def closest_on_segment(px, py, x0, y0, x1, y1):
    """The point of segment (x0, y0)-(x1, y1) closest to (px, py): (qx, qy, u), where
    u in [0, 1] is its fraction along the segment (0 or 1 at an end point)."""
    ex, ey = x1 - x0, y1 - y0
    length2 = ex * ex + ey * ey
    u = 0.0 if length2 == 0.0 else min(max(((px - x0) * ex + (py - y0) * ey) / length2, 0.0), 1.0)
    return x0 + u * ex, y0 + u * ey, u


@kernel
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


@kernel
def segment_contact(px, py, segment):
    """Where a centre (px, py) meets segment (4,): (nx, ny, distance, qx, qy, u) — the unit
    normal from the closest point q towards the centre, their distance, q, and q's fraction
    u along the segment."""
    x0, y0, x1, y1 = segment[0], segment[1], segment[2], segment[3]
    qx, qy, u = closest_on_segment(px, py, x0, y0, x1, y1)
    nx, ny, distance = contact_normal(px, py, qx, qy, x0, y0, x1, y1)
    return nx, ny, distance, qx, qy, u


@kernel
def clip_step(p, q, t0, t1):
    """One Liang–Barsky step: narrow a segment's parameter range [t0, t1] to the half-plane
    p·t <= q. Returns the new range, empty (t0 > t1) if nothing is left."""
    if p == 0.0:  # parallel to this edge: all in or all out
        return (t0, t1) if q >= 0.0 else (1.0, 0.0)
    t = q / p
    if p < 0.0:
        return max(t0, t), t1
    return t0, min(t1, t)


@kernel
def segment_meets_rect(x0, y0, x1, y1, left, bottom, right, top):
    """Does the segment (x0, y0)-(x1, y1) meet the closed rectangle? (Liang–Barsky)"""
    dx, dy = x1 - x0, y1 - y0
    lo, hi = clip_step(-dx, x0 - left, 0.0, 1.0)
    lo, hi = clip_step(dx, right - x0, lo, hi)
    lo, hi = clip_step(-dy, y0 - bottom, lo, hi)
    lo, hi = clip_step(dy, top - y0, lo, hi)
    return lo <= hi
