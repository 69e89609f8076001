"""The contact rows of one step: every contact the solver (response/solver.py) must hold.

Rows are made from the state at the *start* of the step, before anything moves:

* pairs of bodies whose gap is less than what the two could close in the step (their
  speculative margins, `margins`): a pair still apart is a *speculative* row, which only
  acts if the step would close the gap past zero (so an impact stops the bodies where they
  meet instead of sinking one into the other, and a ball resting on a ball is held by it);
* a body and a box wall, when the body is within its margin of the wall and either meets it
  slower than the rest speed (it rests there) or touches another body this step (a pile must be
  held by the floor in the same solve as by its neighbours). A lone body's fast impact is left
  to the wall bounce (response/statics.py), which reflects the overshoot exactly.

Each row has a unit normal from body i toward body j (into the wall for a wall row), the gap
along it (negative for an overlap), the effective mass along it, the relative normal velocity at
the start of the step (`approach`, negative when closing) and the point where the bodies meet.
Rows are in canonical order — pairs in (i, j) order, then walls in (body, wall) order — so the
same input gives the same bytes whichever broad phase found the pairs.
"""
from collections import namedtuple

import numpy as np
from numba import njit

from ..geometry.box import wall_geometry
from ..geometry.toi import time_to_pair
from ..model.kinds import CIRCLE
from ..narrowphase.registry import contact

SLOP = 0.005   # of the smaller radius: an overlap the solver tolerates between bodies (solver.py)
MARGIN = 0.01  # of the radius: every body's smallest speculative margin (a resting pile that falls
               # ½·g·dt² between two steps must not lose its rows to rounding)

Rows = namedtuple("Rows", ["i", "j", "wall", "normal", "point", "gap", "mass", "approach", "hit", "impulse",
                           "pseudo", "slop"])
Rows.__doc__ = """Contact rows, each (k,) or (k, 2): i, j the bodies (j = -1 for a wall row, whose
side is `wall`, else -1); normal unit, from i toward j (into the wall); point where they meet; gap
along the normal at the start of the step (< 0: overlapping); mass the effective mass along the
normal, 1 / (1/m_i + 1/m_j); approach (v_j - v_i)·n at the start of the step; impulse and pseudo
the impact impulse, the accumulated contact impulse and position impulse (set by the solver); slop the overlap the
row tolerates."""


@njit(cache=True)
def new_rows(capacity):
    k = max(capacity, 1)
    return Rows(np.empty(k, np.int64), np.empty(k, np.int64), np.empty(k, np.int64), np.empty((k, 2)),
                np.empty((k, 2)), np.empty(k), np.empty(k), np.empty(k), np.zeros(k), np.zeros(k), np.zeros(k),
                np.empty(k))


@njit(cache=True)
def margins(velocities, accelerations, radii, dt, out):
    """Each body's speculative margin (n,): how far it can move in a step of dt, capped at its
    radius (a faster body may still tunnel: that is the discrete method's known limit), and at
    least MARGIN of its radius."""
    for i in range(radii.shape[0]):
        speed = np.hypot(velocities[i, 0], velocities[i, 1])
        pull = np.hypot(accelerations[i, 0], accelerations[i, 1])
        out[i] = max(min(speed * dt + pull * dt * dt, radii[i]), MARGIN * radii[i])


@njit(cache=True)
def _approach(velocities, i, j, nx, ny):
    if j < 0:
        return -(velocities[i, 0] * nx + velocities[i, 1] * ny)
    return (velocities[j, 0] - velocities[i, 0]) * nx + (velocities[j, 1] - velocities[i, 1]) * ny


@njit(cache=True)
def _circles_at_contact(positions, velocities, radii, i, j, dt, nx, ny, depth, px, py):
    """Two circles still apart that touch within the step: their contact where they meet, the
    normal at the time of contact t (uniform gravity cancels between them) and the gap closed
    until then along it, -(v_j - v_i)·n·t. Taking the normal at the start of the step instead
    would turn an oblique impact by the distance the bodies slide past each other before they
    meet. The contact as given if they do not touch within the step."""
    dx, dy = positions[j, 0] - positions[i, 0], positions[j, 1] - positions[i, 1]
    dvx, dvy = velocities[j, 0] - velocities[i, 0], velocities[j, 1] - velocities[i, 1]
    reach = radii[i] + radii[j]
    t = time_to_pair(dx, dy, dvx, dvy, reach, dt)
    if not t < np.inf:
        return nx, ny, depth, px, py
    cx, cy = (dx + dvx * t) / reach, (dy + dvy * t) / reach
    gap = -(dvx * cx + dvy * cy) * t
    x, y = positions[i, 0] + velocities[i, 0] * t, positions[i, 1] + velocities[i, 1] * t
    return cx, cy, -gap, x + radii[i] * cx, y + radii[i] * cy


@njit(cache=True)
def pair_rows(shapes, positions, velocities, masses, radii, margin, dt, pairs, rows):
    """Fill rows with the pairs (k, 2) (canonical order, i < j) whose gap is under the sum of
    their margins. Returns the number of rows; touched (n,) bool marks bodies in a row."""
    count = 0
    for c in range(pairs.shape[0]):
        i, j = pairs[c, 0], pairs[c, 1]
        nx, ny, depth, px, py = contact(shapes, positions, radii, i, j)
        if -depth >= margin[i] + margin[j]:
            continue
        if depth < 0.0 and shapes[i] == CIRCLE and shapes[j] == CIRCLE:
            nx, ny, depth, px, py = _circles_at_contact(positions, velocities, radii, i, j, dt, nx, ny, depth,
                                                        px, py)
        rows.i[count], rows.j[count], rows.wall[count] = i, j, -1
        rows.normal[count, 0], rows.normal[count, 1] = nx, ny
        rows.point[count, 0], rows.point[count, 1] = px, py
        rows.gap[count] = -depth
        rows.mass[count] = 1.0 / (1.0 / masses[i] + 1.0 / masses[j])
        rows.approach[count] = _approach(velocities, i, j, nx, ny)
        rows.slop[count] = SLOP * min(radii[i], radii[j])
        count += 1
    return count


@njit(cache=True)
def wall_rows(positions, velocities, masses, radii, margin, box, rest_speed, in_pair, rows, start):
    """Append after rows[:start] the rows of bodies held by a box wall (see the module's rule).
    in_pair (n,) bool: bodies in a pair row. Returns the new row count."""
    count = start
    for i in range(positions.shape[0]):
        for wall in range(4):
            axis, bound, inward = wall_geometry(box, wall, radii[i])
            gap = (positions[i, axis] - bound) * inward
            if gap >= margin[i]:
                continue
            closing = -velocities[i, axis] * inward   # > 0: moving toward the wall
            if closing > rest_speed and not in_pair[i]:
                continue   # a lone fast impact: the exact wall bounce takes it
            nx, ny = (-inward, 0.0) if axis == 0 else (0.0, -inward)
            rows.i[count], rows.j[count], rows.wall[count] = i, -1, wall
            rows.normal[count, 0], rows.normal[count, 1] = nx, ny
            rows.point[count, 0] = positions[i, 0] + nx * radii[i]
            rows.point[count, 1] = positions[i, 1] + ny * radii[i]
            rows.gap[count] = gap
            rows.mass[count] = masses[i]
            rows.approach[count] = -closing
            rows.slop[count] = 0.0   # a wall cannot give way: no overlap is tolerated
            count += 1
    return count
