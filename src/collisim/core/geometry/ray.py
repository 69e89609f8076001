"""A ray against one shape: how far along the ray it first touches the shape, and the surface
normal there.

A ray is the half-line o + t·u, t >= 0, u a unit vector; each test returns the smallest t at
which the ray touches the shape (the caller compares it with its max_distance), or inf for a
miss. Touching counts, as everywhere in the package: a ray grazing a circle, or passing
through a segment's end point, hits it. Every normal returned is a unit vector facing the ray,
n · u <= 0, except for a ray that starts inside a solid, which gets (0, 0): there is no surface
between the origin and the solid.

* Circle (centre c, radius r; Box2D v3's b2RayCastCircle). Inside means |o - c| < r, strictly,
  as the computed o - c says; an origin exactly on the circle hits it at t = 0 with the outward
  normal unless the ray points away from the centre (then it misses: a ray leaving a surface
  does not hit it again). The hit is found from the point q of the ray's line closest to the
  centre, then the half chord sqrt(r² - |q - c|²) back towards the origin. Unlike the textbook
  quadratic, |q - c|² carries no cancellation of two large squares, so grazing rays are
  classified right to within rounding of q itself.
* Convex polygon (vertices counter-clockwise; Box2D v3's b2RayCastPolygon): the ray is clipped
  by each edge's half-plane, entering where it crosses an edge it faces. The hit is the last
  entry, with that edge's outward normal, if no exit comes before it (touching counts: a ray
  along an edge, or through a corner, hits). Inside means strictly inside every edge's line;
  an origin on the outline hits at t = 0 when the ray points in, or along an edge with the
  polygon beside it, and misses when it points out.
* Thin segment: two-sided, no thickness, closed (end points included). The normal is the
  segment's perpendicular on the ray's side. A ray running along the segment's own line hits
  it at the nearer end point (t = 0 if the origin lies on the segment) with normal -u: seen
  edge on, the segment's end faces the ray head on (a thin capsule's end cap in the limit of
  zero radius). An origin on a segment crossed by the ray gives t = 0 with the perpendicular.
* The box walls: the world is [x0, x1] × [y0, y1] and everything outside is solid. A ray from
  inside hits the wall it leaves through, with the wall's inward normal; an origin outside is
  inside the solid. An origin on a wall, pointing out or along it, touches it at t = 0.
"""
import math

import numpy as np

from ..compiling import kernel
from .box import wall_geometry


@kernel
def cross(ax, ay, bx, by):
    """The z component of a × b."""
    return ax * by - ay * bx


@kernel
def nonnegative(t):
    """t clipped at 0 from below, as +0.0: a ray starting on a surface divides 0 by a negative
    number (-0.0), and rounding can leave a hit known to be ahead of the origin a hair behind."""
    return t if t > 0.0 else 0.0


@kernel
def facing_perpendicular(nx, ny, ux, uy):
    """A unit normal (nx, ny) that faces away from u by rounding only (a grazing ray) turned
    into u's exact perpendicular on the same side: its dot product with u is then exactly 0
    (-uy·ux + ux·uy cancels bit for bit)."""
    if nx * ux + ny * uy <= 0.0:
        return nx, ny
    if cross(ux, uy, nx, ny) >= 0.0:
        return -uy, ux
    return uy, -ux


@kernel
def ray_circle(ox, oy, ux, uy, cx, cy, r):
    """Where the ray o + t·u meets the circle (c, r): (t, nx, ny, inside).

    inside: the origin is strictly inside (t = 0, normal (0, 0)). A miss is t = inf.
    """
    sx, sy = ox - cx, oy - cy  # the origin seen from the centre
    distance2, rr = sx * sx + sy * sy, r * r
    if distance2 < rr:
        return 0.0, 0.0, 0.0, True
    along = sx * ux + sy * uy  # how fast the distance to the centre grows
    if along > 0.0:
        return np.inf, 0.0, 0.0, False  # outside (or on) and moving away: never
    if distance2 == rr:
        length = math.hypot(sx, sy)  # on the circle, moving in or along it: touching now
        return 0.0, sx / length, sy / length, False
    t_closest = -along
    qx, qy = sx + t_closest * ux, sy + t_closest * uy  # the line's point nearest the centre
    qq = qx * qx + qy * qy
    if qq > rr:
        return np.inf, 0.0, 0.0, False
    # Back from q by the half chord. The origin is outside, so t >= 0 but for rounding.
    t = nonnegative(t_closest - math.sqrt(rr - qq))
    px, py = sx + t * ux, sy + t * uy
    length = math.hypot(px, py)
    nx, ny = facing_perpendicular(px / length, py / length, ux, uy)
    return t, nx, ny, False


@kernel
def ray_polygon(ox, oy, ux, uy, vertices, first, end):
    """Where the ray o + t·u meets the convex polygon vertices[first:end] (counter-clockwise):
    (t, nx, ny, inside); a miss is t = inf, inside as for ray_circle."""
    lower, upper, entered, strictly_inside = 0.0, np.inf, -1, True
    enter_nx, enter_ny, along_nx, along_ny, along = 0.0, 0.0, 0.0, 0.0, False
    for k in range(first, end):
        following = k + 1 if k + 1 < end else first
        ex, ey = vertices[following, 0] - vertices[k, 0], vertices[following, 1] - vertices[k, 1]
        length = math.hypot(ex, ey)
        nx, ny = ey / length, -ex / length           # outward: the interior is on the edge's left
        room = nx * (vertices[k, 0] - ox) + ny * (vertices[k, 1] - oy)   # > 0: o inside this edge's line
        strictly_inside = strictly_inside and room > 0.0
        approach = nx * ux + ny * uy
        if approach == 0.0:
            if room < 0.0:
                return np.inf, 0.0, 0.0, False       # parallel to the edge, outside its line
            if room == 0.0:                          # running along the edge's own line
                along, along_nx, along_ny = True, nx, ny
            continue
        t = room / approach
        if approach < 0.0:                           # crossing into the edge's half-plane
            if t >= lower:
                lower, entered, enter_nx, enter_ny = t, k, nx, ny
        elif t < upper:                              # crossing out of it
            upper = t
        if upper < lower:
            return np.inf, 0.0, 0.0, False
    if strictly_inside:
        return 0.0, 0.0, 0.0, True
    if entered < 0:   # on the outline: touching along an edge, or leaving
        return (0.0, along_nx, along_ny, False) if along and upper > 0.0 else (np.inf, 0.0, 0.0, False)
    return nonnegative(lower), enter_nx, enter_ny, False


@kernel
def ray_segment(ox, oy, ux, uy, x0, y0, x1, y1):
    """Where the ray o + t·u meets the thin segment (x0, y0)-(x1, y1): (t, nx, ny); t = inf
    for a miss."""
    ex, ey = x1 - x0, y1 - y0
    wx, wy = x0 - ox, y0 - oy  # the segment's start seen from the origin
    denominator = cross(ux, uy, ex, ey)
    if denominator == 0.0:
        return ray_along_segment(ox, oy, ux, uy, x0, y0, x1, y1)
    # o + t·u = (x0, y0) + s·e, crossed with e and with u.
    t = cross(wx, wy, ex, ey) / denominator
    s = cross(wx, wy, ux, uy) / denominator
    if not (t >= 0.0 and 0.0 <= s <= 1.0):
        return np.inf, 0.0, 0.0
    length = math.hypot(ex, ey)
    nx, ny = -ey / length, ex / length
    if nx * ux + ny * uy > 0.0:  # the side the ray comes from
        nx, ny = -nx, -ny
    return nonnegative(t), nx, ny


@kernel
def ray_along_segment(ox, oy, ux, uy, x0, y0, x1, y1):
    """A segment parallel to the ray (or a single point): it is hit only if it lies on the
    ray's line, at its nearer end, with normal -u. Returns (t, nx, ny)."""
    if cross(x0 - ox, y0 - oy, ux, uy) != 0.0 or cross(x1 - ox, y1 - oy, ux, uy) != 0.0:
        return np.inf, 0.0, 0.0  # beside the ray's line
    t0 = (x0 - ox) * ux + (y0 - oy) * uy
    t1 = (x1 - ox) * ux + (y1 - oy) * uy
    if max(t0, t1) < 0.0:
        return np.inf, 0.0, 0.0  # behind the origin
    return nonnegative(min(t0, t1)), -ux, -uy


@kernel
def outside_wall(ox, oy, box):
    """The first wall (kinds.WALL_SIDES order) whose solid side holds the point, or -1 if it
    lies in the closed box. box: (4,) xmin, ymin, xmax, ymax."""
    for wall in range(4):
        axis, bound, inward = wall_geometry(box, wall, 0.0)
        coordinate = ox if axis == 0 else oy
        if (coordinate - bound) * inward < 0.0:
            return wall
    return -1


@kernel
def ray_walls(ox, oy, ux, uy, box):
    """Where the ray o + t·u from inside the box leaves it: (t, wall, nx, ny, inside).

    box: (4,) xmin, ymin, xmax, ymax; wall numbered as kinds.WALL_SIDES. The normal is the
    wall's inward normal. At a corner the x wall (the lower number) is reported. An origin
    outside the box is inside the solid: t = 0, normal (0, 0), inside True, wall from
    outside_wall.
    """
    wall = outside_wall(ox, oy, box)
    if wall >= 0:
        return 0.0, wall, 0.0, 0.0, True
    best_t, best_wall = np.inf, -1
    for axis in range(2):
        o, u = (ox, ux) if axis == 0 else (oy, uy)
        if u != 0.0:
            wall = 2 * axis + (1 if u > 0.0 else 0)  # the side it travels towards
            bound = wall_geometry(box, wall, 0.0)[1]
            t = nonnegative((bound - o) / u)  # when it reaches the wall's line
        elif o == box[axis] or o == box[axis + 2]:
            wall, t = 2 * axis + (0 if o == box[axis] else 1), 0.0  # sliding along a wall
        else:
            continue
        if t < best_t:
            best_t, best_wall = t, wall
    axis, _, inward = wall_geometry(box, best_wall, 0.0)
    return best_t, best_wall, inward if axis == 0 else 0.0, inward if axis == 1 else 0.0, False
