"""Time of impact (TOI): when does a moving circle first touch something?

Discrete collision detection only looks for overlaps at frame times, so a fast
circle can jump over a thin wall, or over another circle, between two frames
("tunnelling"). Continuous collision detection instead writes the motion during
the step as a function of time,

    p(t) = p + v t + ½ a t²        (constant acceleration a, e.g. gravity)

and solves the contact condition for the first time t_c at which it holds:

* wall:     the centre reaches the wall line moved inwards by the radius,
            x(t) = bound (a quadratic in t, linear when a = 0);
* pair:     the centres are r_i + r_j apart, |Δp + Δv t| = r_i + r_j; a uniform
            gravity is the same for both circles and cancels in the differences,
            leaving a quadratic in t;
* segment:  the centre is at distance r from the segment: either on one of the two
            lines parallel to it at distance r ("faces", hit between the end points)
            or on the circle of radius r around an end point ("caps").

Every function returns the earliest impact time in [0, t_max], or inf. Only
*approaching* contacts count: touching (or overlapping) while closing in is an
impact at t = 0, but touching while separating is not an impact at all. That rule
is what stops a collision that was just resolved from being found again at t + 0
because of rounding.

Numerical care, which is most of the art:

* Quadratic roots are never taken as (-b - sqrt(b² - ac)) / a: for a grazing
  contact or a tiny gap that subtracts two nearly equal numbers and loses every
  digit. The same root is c / (-b + sqrt(b² - ac)), where both terms add.
* For pairs, b² - ac equals a·R² - (Δp × Δv)² (Lagrange's identity), which keeps
  the grazing classification exact: it is |Δv|² (R² - impact parameter²).
* With acceleration, the distance to a point (a segment's cap, or a circle whose
  acceleration differs, e.g. one resting on the floor) is a quartic; roots.py
  isolates its real roots without a closed formula.
"""
import math

import numpy as np

from ..compiling import kernel
from .roots import first_down_crossing
from .vector import length


@kernel
def is_closing(rate, accel):
    """Does a gap with this rate and acceleration start shrinking now?

    A zero rate with an inward acceleration counts too (a particle resting on a
    floor under gravity is pressed into it).
    """
    return rate < 0.0 or (rate == 0.0 and accel < 0.0)


@kernel
def first_closing_time(gap, rate, accel):
    """First t > 0 where gap + rate t + ½ accel t² reaches 0 while decreasing, or inf.

    A quadratic crosses zero downwards at most once: at its smaller root when it
    opens upwards (accel > 0), at its larger root when it opens downwards. Both
    are the root (-rate - sqrt(disc)) / accel, which is evaluated in whichever of
    its two algebraically equal forms adds numbers of the same sign.
    """
    if accel == 0.0:
        return -gap / rate if (rate < 0.0 and gap > 0.0) else np.inf
    disc = rate * rate - 2.0 * accel * gap
    if disc < 0.0:
        return np.inf
    root = math.sqrt(disc)
    if rate < 0.0:
        t = 2.0 * gap / (root - rate)
    else:
        t = -(rate + root) / accel
    return t if t > 0.0 else np.inf


@kernel
def time_to_wall(x, v, a, bound, side, t_max):
    """Time for a coordinate x(t) = x + v t + ½ a t² to reach `bound` from inside.

    bound is the wall already moved in by the radius. side = -1.0 for a lower wall
    (inside is x >= bound), +1.0 for an upper wall (inside is x <= bound).
    Returns t in [0, t_max] or inf: 0 when touching and approaching; a receding
    particle has no impact now, but under acceleration it may come back later.
    """
    gap = side * (bound - x)
    rate = -side * v
    accel = -side * a
    if gap <= 0.0 and is_closing(rate, accel):
        return 0.0
    # The engine never lets a particle really leave the box: a negative gap is
    # rounding, and treating it as touching makes sure the particle comes back.
    t = first_closing_time(max(gap, 0.0), rate, accel)
    return t if t <= t_max else np.inf


@kernel
def time_to_pair(dx, dy, dvx, dvy, rsum, t_max):
    """Time for two circles to touch: |d + dv t| = rsum, without relative acceleration.

    d = p_j - p_i and dv = v_j - v_i (uniform gravity cancels). With
    a = dv·dv, b = d·dv, c = d·d - rsum², the impact is the smaller root of
    a t² + 2 b t + c = 0, computed as c / (-b + sqrt(b² - ac)).
    Returns t in [0, t_max] or inf (receding, missing or grazing).
    """
    b = dx * dvx + dy * dvy
    if b >= 0.0:
        return np.inf
    c = dx * dx + dy * dy - rsum * rsum
    if c <= 0.0:
        return 0.0
    a = dvx * dvx + dvy * dvy
    cross = dx * dvy - dy * dvx
    disc = a * rsum * rsum - cross * cross
    if disc <= 0.0:
        return np.inf
    t = c / (-b + math.sqrt(disc))
    return t if t <= t_max else np.inf


@kernel
def contact_quartic(dx, dy, vx, vy, ax, ay, dist):
    """The 5 coefficients of |d + v t + ½ a t²|² - dist², lowest order first (roots.py)."""
    return (dx * dx + dy * dy - dist * dist,
            2.0 * (dx * vx + dy * vy),
            vx * vx + vy * vy + dx * ax + dy * ay,
            vx * ax + vy * ay,
            0.25 * (ax * ax + ay * ay))


@kernel
def time_to_point(dx, dy, vx, vy, ax, ay, dist, t_max):
    """Time for a point moving as d + v t + ½ a t² (relative to a fixed point) to come
    within `dist` of it while approaching, or inf.

    Without acceleration this is time_to_pair (closed form). With it, the squared
    distance minus dist² is a quartic f(t); the impact is its first downward zero
    crossing, found by monotone-piece isolation and a bracketed Newton search
    (roots.py) on [0, t_max] — capped by Cauchy's bound on the roots, beyond
    which f > 0.
    """
    if ax == 0.0 and ay == 0.0:  # pairs under one uniform gravity: the common case, in closed form
        return time_to_pair(dx, dy, vx, vy, dist, t_max)
    coeffs = contact_quartic(dx, dy, vx, vy, ax, ay, dist)
    if coeffs[4] == 0.0:  # so little acceleration that its square underflows
        return time_to_pair(dx, dy, vx, vy, dist, t_max)
    if coeffs[0] <= 0.0 and is_closing(coeffs[1], coeffs[2]):
        return 0.0
    # Overlapping but not closing in: treat the overlap as touching (it is rounding,
    # or an initial overlap), so the impact is when the distance comes back to what
    # it is now, instead of the two sinking into each other.
    coeffs = (max(coeffs[0], 0.0), coeffs[1], coeffs[2], coeffs[3], coeffs[4])
    root_bound = 1.0 + max(max(abs(coeffs[0]), abs(coeffs[1])), max(abs(coeffs[2]), abs(coeffs[3]))) / coeffs[4]
    t_hi = min(t_max, root_bound)
    # Cheap rejections: even heading straight for the point, it cannot get there; or its
    # distance along the line it starts on (a lower bound of the distance) stays above dist
    # (a body beside or below another under gravity, or moving away from it).
    distance = length(dx, dy)
    closest = distance - length(vx, vy) * t_hi - 0.5 * length(ax, ay) * t_hi * t_hi
    if closest > dist or _stays_beyond(distance, (dx * vx + dy * vy) / distance, (dx * ax + dy * ay) / distance,
                                       dist * (1.0 + 1e-12), t_hi):
        return np.inf
    return first_down_crossing(coeffs, 0.0, t_hi)


@kernel
def _stays_beyond(s, s_rate, s_acc, bound, t_hi):
    """Does s + s_rate t + ½ s_acc t² stay above bound for every t in [0, t_hi]?"""
    lowest = min(s, s + (s_rate + 0.5 * s_acc * t_hi) * t_hi)
    if s_acc > 0.0 and 0.0 < -s_rate / s_acc < t_hi:   # a minimum inside: at the vertex
        lowest = s - 0.5 * s_rate * s_rate / s_acc
    return lowest > bound


@kernel
def side_of_line(s, s_rate, s_acc):
    """+1.0 or -1.0: the side of a line a centre at signed distance s is on (or, when
    exactly on it, the side it comes from)."""
    if s != 0.0:
        return math.copysign(1.0, s)
    if s_rate != 0.0:
        return -math.copysign(1.0, s_rate)
    return -math.copysign(1.0, s_acc) if s_acc != 0.0 else 1.0


@kernel
def time_to_faces(px, py, vx, vy, ax, ay, r, x0, y0, x1, y1, t_max):
    """Circle against the interior of segment (x0, y0)-(x1, y1): (t, nx, ny) or (inf, 0, 0).

    In the segment's frame, s is the signed distance of the centre along the unit
    normal and w its coordinate along the segment (0 <= w <= length between the end
    points). The circle touches the interior when |s| = r with 0 <= w <= length:
    each face is a 1D "wall" for s, so each is a first_closing_time, accepted when
    w is within the segment at that time. The normal points towards the circle.
    """
    ex, ey = x1 - x0, y1 - y0
    length = math.hypot(ex, ey)
    if length == 0.0:
        return np.inf, 0.0, 0.0
    ux, uy = ex / length, ey / length
    nx, ny = -uy, ux
    rx, ry = px - x0, py - y0
    s, s_rate, s_acc = rx * nx + ry * ny, vx * nx + vy * ny, ax * nx + ay * ny
    w, w_rate, w_acc = rx * ux + ry * uy, vx * ux + vy * uy, ax * ux + ay * uy
    t_best, side_best = np.inf, 0.0
    if abs(s) <= r and 0.0 <= w <= length:
        # Already touching (or overlapping) the interior: an impact now if closing in;
        # otherwise, as for a wall, the overlap counts as touching, and the impact is
        # when the particle comes back to it.
        side = side_of_line(s, s_rate, s_acc)
        if is_closing(side * s_rate, side * s_acc):
            return 0.0, side * nx, side * ny
        t = first_closing_time(0.0, side * s_rate, side * s_acc)
        if t <= t_max and 0.0 <= w + (w_rate + 0.5 * w_acc * t) * t <= length:
            t_best, side_best = t, side
    for side in (1.0, -1.0):
        t = first_closing_time(side * s - r, side * s_rate, side * s_acc)
        if t <= t_max and t < t_best and 0.0 <= w + (w_rate + 0.5 * w_acc * t) * t <= length:
            t_best, side_best = t, side
    return t_best, side_best * nx, side_best * ny


@kernel
def time_to_segment(px, py, vx, vy, ax, ay, r, x0, y0, x1, y1, t_max):
    """Earliest impact of a circle (centre p, velocity v, acceleration a, radius r)
    with the segment (x0, y0)-(x1, y1), which collides on both sides and has round
    end caps. Returns (t, nx, ny): t in [0, t_max] or inf, and the unit contact
    normal at impact, pointing from the segment towards the circle.

    The region the centre must not enter is the segment thickened by r: two faces
    (time_to_faces) and two half-discs around the end points, where the impact is
    the point-circle contact |p(t) - q| = r (time_to_point: closed form without
    acceleration, a quartic solved by root isolation with it).
    """
    t_best, nx_best, ny_best = time_to_faces(px, py, vx, vy, ax, ay, r, x0, y0, x1, y1, t_max)
    for qx, qy in ((x0, y0), (x1, y1)):
        dx, dy = px - qx, py - qy
        t = time_to_point(dx, dy, vx, vy, ax, ay, r, min(t_best, t_max))
        if t < t_best:
            cx = dx + (vx + 0.5 * ax * t) * t
            cy = dy + (vy + 0.5 * ay * t) * t
            norm = math.hypot(cx, cy)
            t_best, nx_best, ny_best = t, cx / norm, cy / norm
    return t_best, nx_best, ny_best
