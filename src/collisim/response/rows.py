"""The contact rows of one step: every contact point the solver (response/solver.py) must hold.

Rows are made from the state at the *start* of the step, before anything moves:

* pairs of bodies whose gap is less than what the two could close in the step (their
  speculative margins, `margins`): a pair still apart gives *speculative* rows, which only act
  if the step would close the gap past zero (so an impact stops the bodies where they meet
  instead of sinking one into the other, and a ball resting on a ball is held by it);
* a polygon and a segment within its margin (segment_rows; circles meet segments in the
  statics phase, response/statics.py);
* a body and a box wall: a polygon within its margin of the wall always; a circle when it is
  within its margin and either meets the wall slower than the rest speed (it rests there) or
  touches another body this step (a pile must be held by the floor in the same solve as by its
  neighbours). A lone circle's fast impact is left to the wall bounce (response/statics.py),
  which reflects the overshoot exactly.

A manifold (narrowphase/manifold.py) gives one row per point: two for a face on a face. Each row
has a unit normal from body i toward body j (into the wall), its point, the point's arm from
each centre, the gap along the normal (negative for an overlap) and the effective masses along
the normal and the tangent. Rows are in canonical order — pairs in (i, j) order, then walls in
(body, wall) order, points in manifold order — so the same input gives the same bytes whichever
broad phase found the pairs.
"""
from collections import namedtuple

import numpy as np
from numba import njit

from ..geometry.box import wall_geometry
from ..geometry.toi import time_to_pair
from ..model.kinds import CIRCLE, N_WALLS
from ..narrowphase.manifold import pair_manifold, polygon_segment_manifold, polygon_wall_manifold

SLOP = 0.005   # of the smaller radius: an overlap the solver tolerates between bodies (solver.py)
MARGIN = 0.01  # of the radius: every body's smallest speculative margin (a resting pile that falls
               # ½·g·dt² between two steps must not lose its rows to rounding)

Rows = namedtuple("Rows", ["i", "j", "wall", "feature", "partner", "normal", "point", "lever", "gap",
                           "mass", "mass_t", "hit", "impulse", "friction", "pseudo", "slop"])
Rows.__doc__ = """Contact rows, each (k,) or (k, 2): i, j the bodies (j = -1 for a row of a static: `wall` is the
box wall's side, or N_WALLS + k for segment k; else -1); feature the point's number in its
manifold (0 or 1); partner the row of the manifold's other point, or -1; normal unit, from i
toward j (into the wall); point where they meet; lever (k, 4) the turning lever of the point
about each centre, arm × n and arm × t for body i then body j (0 for a wall): a unit impulse
along n turns body i by -lever[0]/I_i, and the point's velocity along n includes ω_i·lever[0];
gap along the normal at the start of the step (< 0: overlapping); mass, mass_t the effective
masses along the normal and the tangent (-n_y, n_x); hit the impact impulse, impulse and
friction the accumulated contact impulses along the normal and the tangent, pseudo the position
impulse (set by the solver); slop the overlap the row tolerates."""


@njit(cache=True)
def new_rows(capacity):
    k = max(capacity, 1)
    ints, reals, pairs = (lambda: np.empty(k, np.int64)), (lambda: np.zeros(k)), (lambda: np.empty((k, 2)))
    return Rows(ints(), ints(), ints(), ints(), ints(), pairs(), pairs(), np.zeros((k, 4)), reals(), reals(),
                reals(), reals(), reals(), reals(), reals(), reals())


@njit(cache=True)
def margins(velocities, angular_velocities, accelerations, radii, dt, out):
    """Each body's speculative margin (n,): how far any of its points can move in a step of dt,
    capped at its radius (a faster body may still tunnel: that is the discrete method's known
    limit), and at least MARGIN of its radius."""
    for i in range(radii.shape[0]):
        speed = np.hypot(velocities[i, 0], velocities[i, 1]) + abs(angular_velocities[i]) * radii[i]
        pull = np.hypot(accelerations[i, 0], accelerations[i, 1])
        out[i] = max(min(speed * dt + pull * dt * dt, radii[i]), MARGIN * radii[i])


@njit(cache=True, inline="always")
def _effective_masses(rows, r, masses, inertias):
    """Row r's effective masses along the normal and the tangent: 1 / (the velocity change at the
    point along that direction per unit impulse along it)."""
    i, j, lever = rows.i[r], rows.j[r], rows.lever[r]
    normal = 1.0 / masses[i] + lever[0] * lever[0] / inertias[i]
    tangent = 1.0 / masses[i] + lever[1] * lever[1] / inertias[i]
    if j >= 0:
        normal += 1.0 / masses[j] + lever[2] * lever[2] / inertias[j]
        tangent += 1.0 / masses[j] + lever[3] * lever[3] / inertias[j]
    rows.mass[r], rows.mass_t[r] = 1.0 / normal, 1.0 / tangent


@njit(cache=True, inline="always")
def _set_levers(rows, r, ax_i, ay_i, ax_j, ay_j, masses, inertias):
    """Row r's levers from the point's arms from each centre, and its effective masses."""
    nx, ny = rows.normal[r, 0], rows.normal[r, 1]
    lever = rows.lever[r]
    lever[0], lever[1] = ax_i * ny - ay_i * nx, ax_i * nx + ay_i * ny
    lever[2], lever[3] = 0.0, 0.0
    if rows.j[r] >= 0:
        lever[2], lever[3] = ax_j * ny - ay_j * nx, ax_j * nx + ay_j * ny
    _effective_masses(rows, r, masses, inertias)


@njit(cache=True, inline="always")
def _add(rows, r, i, j, wall, feature, nx, ny, gap, px, py, positions, masses, inertias, slop):
    """Row r: a contact point of bodies i and j (or a wall) at (px, py), `gap` apart along n."""
    rows.i[r], rows.j[r], rows.wall[r], rows.feature[r], rows.partner[r] = i, j, wall, feature, -1
    rows.normal[r, 0], rows.normal[r, 1] = nx, ny
    rows.point[r, 0], rows.point[r, 1] = px, py
    ax_j, ay_j = (px - positions[j, 0], py - positions[j, 1]) if j >= 0 else (0.0, 0.0)
    _set_levers(rows, r, px - positions[i, 0], py - positions[i, 1], ax_j, ay_j, masses, inertias)
    rows.gap[r], rows.slop[r] = gap, slop
    rows.hit[r] = rows.impulse[r] = rows.friction[r] = rows.pseudo[r] = 0.0


@njit(cache=True, inline="always")
def _add_manifold(rows, count, m, i, j, wall, margin, positions, masses, inertias, slop):
    """The points of manifold m closer than margin, as rows from `count`. Returns the new count."""
    nx, ny, points = m[0], m[1], m[2]
    first = count
    for k in range(points):
        depth, px, py = (m[3], m[4], m[5]) if k == 0 else (m[6], m[7], m[8])
        if -depth < margin:
            _add(rows, count, i, j, wall, k, nx, ny, -depth, px, py, positions, masses, inertias, slop)
            count += 1
    if count - first == 2:
        rows.partner[first], rows.partner[first + 1] = first + 1, first
    return count


@njit(cache=True)
def _circles_at_contact(positions, velocities, radii, i, j, dt, m):
    """Two circles still apart that touch within the step: their manifold where they meet, with
    the normal at the time of contact t (uniform gravity cancels between them) and the gap closed
    until then along it, -(v_j - v_i)·n·t. Taking the normal at the start of the step instead
    would turn an oblique impact by the distance the bodies slide past each other before they
    meet. Manifold m as it is if they do not touch within the step."""
    dx, dy = positions[j, 0] - positions[i, 0], positions[j, 1] - positions[i, 1]
    dvx, dvy = velocities[j, 0] - velocities[i, 0], velocities[j, 1] - velocities[i, 1]
    reach = radii[i] + radii[j]
    t = time_to_pair(dx, dy, dvx, dvy, reach, dt)
    if not t < np.inf:
        return m
    nx, ny = (dx + dvx * t) / reach, (dy + dvy * t) / reach
    gap = -(dvx * nx + dvy * ny) * t
    x, y = positions[i, 0] + velocities[i, 0] * t, positions[i, 1] + velocities[i, 1] * t
    return nx, ny, 1, -gap, x + radii[i] * nx, y + radii[i] * ny, 0.0, 0.0, 0.0


@njit(cache=True, inline="always")
def _on_line_of_centres(rows, r, radius_i, radius_j, masses, inertias):
    """Row r of two circles (or a circle and a wall, radius_j 0): they touch on their line of
    centres, so a push along it turns neither (lever exactly 0: the product of the rounded arm
    with the normal would leave a residue that sets circles spinning), and friction turns each
    by its radius."""
    lever = rows.lever[r]
    lever[0], lever[1], lever[2], lever[3] = 0.0, radius_i, 0.0, -radius_j
    _effective_masses(rows, r, masses, inertias)


@njit(cache=True)
def pair_rows(bodies, vertices, margin, dt, pairs, rows, moved):
    """Fill rows with the contact points of pairs (k, 2) (canonical order, i < j) closer than the
    sum of their margins. Returns the number of rows. moved: scratch for narrowphase/manifold.py."""
    b = bodies
    count = 0
    for c in range(pairs.shape[0]):
        i, j = pairs[c, 0], pairs[c, 1]
        reach = margin[i] + margin[j]
        m = pair_manifold(b.shapes, b.positions, b.radii, vertices, b.vertex_start, i, j, reach, moved)
        circles = b.shapes[i] == CIRCLE and b.shapes[j] == CIRCLE
        if circles and m[2] == 1 and m[3] < 0.0:
            m = _circles_at_contact(b.positions, b.velocities, b.radii, i, j, dt, m)
        first = count
        count = _add_manifold(rows, count, m, i, j, -1, reach, b.positions, b.masses, b.inertias,
                              SLOP * min(b.radii[i], b.radii[j]))
        if circles and count > first:   # two circles meet on their line of centres, wherever that is
            _on_line_of_centres(rows, first, b.radii[i], b.radii[j], b.masses, b.inertias)
    return count


@njit(cache=True)
def wall_rows(bodies, vertices, margin, box, rest_speed, in_pair, rows, start):
    """Append after rows[:start] the rows of bodies held by a box wall (see the module's rule).
    in_pair (n,) bool: bodies in a pair row. Returns the new row count. No overlap of a wall is
    tolerated: a wall cannot give way."""
    b = bodies
    count = start
    for i in range(b.positions.shape[0]):
        for wall in range(4):
            if b.shapes[i] != CIRCLE:
                m = polygon_wall_manifold(vertices, b.vertex_start, i, box, wall, margin[i])
                count = _add_manifold(rows, count, m, i, -1, wall, margin[i], b.positions, b.masses, b.inertias, 0.0)
                continue
            axis, bound, inward = wall_geometry(box, wall, b.radii[i])
            gap = (b.positions[i, axis] - bound) * inward
            if gap >= margin[i]:
                continue
            if -b.velocities[i, axis] * inward > rest_speed and not in_pair[i]:
                continue   # a lone fast impact: the exact wall bounce takes it
            nx, ny = (-inward, 0.0) if axis == 0 else (0.0, -inward)
            reach = b.radii[i] + 0.5 * gap   # midway between the circle and the wall
            _add(rows, count, i, -1, wall, 0, nx, ny, gap, b.positions[i, 0] + reach * nx,
                 b.positions[i, 1] + reach * ny, b.positions, b.masses, b.inertias, 0.0)
            _on_line_of_centres(rows, count, b.radii[i], 0.0, b.masses, b.inertias)
            count += 1
    return count


@njit(cache=True)
def segment_rows(bodies, vertices, margin, segments, rows, start):
    """Append after rows[:start] the rows of polygons within their margin of a segment (m, 4):
    j = -1, wall = N_WALLS + the segment's number. Returns the new row count. A segment, like a
    wall, cannot give way: no overlap is tolerated."""
    b = bodies
    count = start
    for i in range(b.positions.shape[0]):
        if b.shapes[i] == CIRCLE:
            continue
        x, y, reach = b.positions[i, 0], b.positions[i, 1], b.radii[i] + margin[i]
        for k in range(segments.shape[0]):
            if _beyond(segments, k, x, y, reach):
                continue
            m = polygon_segment_manifold(vertices, b.vertex_start, i, segments, k, margin[i])
            count = _add_manifold(rows, count, m, i, -1, N_WALLS + k, margin[i], b.positions, b.masses, b.inertias,
                                  0.0)
    return count


@njit(cache=True)
def _beyond(segments, k, x, y, reach):
    """Is segment k farther than reach from (x, y)? (Its box, grown by reach, misses the point.)"""
    x0, y0, x1, y1 = segments[k, 0], segments[k, 1], segments[k, 2], segments[k, 3]
    return (x < min(x0, x1) - reach or x > max(x0, x1) + reach or y < min(y0, y1) - reach
            or y > max(y0, y1) + reach)


@njit(cache=True)
def near_segments(bodies, margin, segments):
    """How many (polygon, segment) pairs are near enough for segment_rows to look at."""
    b = bodies
    near = 0
    if segments.shape[0] == 0:
        return 0
    for i in range(b.positions.shape[0]):
        if b.shapes[i] != CIRCLE:
            for k in range(segments.shape[0]):
                near += not _beyond(segments, k, b.positions[i, 0], b.positions[i, 1], b.radii[i] + margin[i])
    return near
