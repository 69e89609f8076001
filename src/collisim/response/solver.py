"""The contact solver: every contact of a step solved together, by sequential impulses.

A body's step from p with velocity v under a constant acceleration a is the parabola
p' = p + w·dt with the mean velocity w = v + ½·a·dt, ending with v' = v + a·dt. A contact
impulse P is taken as spread evenly over the step (as a resting contact's force is): it adds
½·P/m to the mean velocity and P/m to the final one. So a ball resting on the floor is pressed by
exactly P = m·g·dt a step, ends the step where it started, and at rest — no micro-bounce, and the
floor's pressure is its weight (wall events log P).

The solve, on the rows of response/rows.py:

1. **warm start**: each row starts from its contact's impulse of the step before (warmstart.py);
2. **velocities** (`iterations` sweeps in row order): the mean relative normal velocity of each
   row may not close more than its gap in the step, w_n >= -max(gap, 0)/dt, with the accumulated
   impulse kept >= 0 (contacts push, never pull). An impact therefore stops the bodies where they
   meet rather than sinking one into the other, and a pile passes its weight down to the floor;
3. **positions** (split impulse, as Box2D and Chipmunk do): an overlap beyond the row's slop is
   removed, a fraction POSITION_RATE of it a step, by pseudo-velocities that move positions and
   are then forgotten — correcting an overlap adds no kinetic energy;
4. **rest**, on the final velocities: the rows that pressed leave at relative normal velocity 0.

Before all this, **impacts** (`collide`): rows that meet within the step faster than the rest
speed get Newton's impulse with restitution e, one after another while any still meets — the
video's two-body response, exact for an isolated pair, and energy-conserving at e = 1 for any
cluster, since every single impulse is. Only what is left — contacts slower than the rest
speed, under gravity — is held by steps 1 to 4.
"""
import numpy as np
from numba import njit

from .impulse import newton_impulse

POSITION_RATE = 0.2   # the fraction of an overlap (beyond the slop) removed per step


@njit(cache=True)
def _relative(velocity, rows, r):
    """(v_j - v_i)·n of row r, for per-body vectors (n, 2); a wall does not move."""
    i, j = rows.i[r], rows.j[r]
    nx, ny = rows.normal[r, 0], rows.normal[r, 1]
    rel = -(velocity[i, 0] * nx + velocity[i, 1] * ny)
    if j >= 0:
        rel += velocity[j, 0] * nx + velocity[j, 1] * ny
    return rel


@njit(cache=True)
def _apply(velocity, masses, rows, r, impulse):
    """Change the per-body vectors (n, 2) by an impulse along row r's normal (i pushed back, j on)."""
    i, j = rows.i[r], rows.j[r]
    nx, ny = rows.normal[r, 0], rows.normal[r, 1]
    velocity[i, 0] -= impulse * nx / masses[i]
    velocity[i, 1] -= impulse * ny / masses[i]
    if j >= 0:
        velocity[j, 0] += impulse * nx / masses[j]
        velocity[j, 1] += impulse * ny / masses[j]


@njit(cache=True)
def _free_closing(rows, count, velocities, accelerations, dt, out):
    """Each row's mean relative normal velocity over the step in free flight (k,)."""
    for r in range(count):
        out[r] = _relative(velocities, rows, r) + 0.5 * dt * _relative(accelerations, rows, r)


@njit(cache=True)
def solve_velocities(rows, count, velocities, accelerations, masses, dt, iterations, push):
    """Steps 1 and 2: the contact impulses rows.impulse and the change they make to each body's
    mean velocity, push (n, 2) (zeroed here). Returns free (k,), the rows' free mean closing."""
    push[:] = 0.0
    free = np.empty(count)
    _free_closing(rows, count, velocities, accelerations, dt, free)
    for r in range(count):
        if rows.impulse[r] > 0.0:
            _apply(push, masses, rows, r, 0.5 * rows.impulse[r])
    for _ in range(iterations):
        for r in range(count):
            target = -max(rows.gap[r], 0.0) / dt
            closing = free[r] + _relative(push, rows, r)
            total = max(rows.impulse[r] + 2.0 * rows.mass[r] * (target - closing), 0.0)
            _apply(push, masses, rows, r, 0.5 * (total - rows.impulse[r]))
            rows.impulse[r] = total
    return free


@njit(cache=True)
def solve_positions(rows, count, free, masses, dt, iterations, push, shift):
    """Step 3: pseudo-velocities shift (n, 2) (zeroed here) that take overlaps beyond the slop
    out at POSITION_RATE a step, given the solved mean velocities (free + push)."""
    shift[:] = 0.0
    rows.pseudo[:count] = 0.0
    for _ in range(iterations):
        for r in range(count):
            excess = -rows.gap[r] - rows.slop[r]
            if excess <= 0.0:
                continue
            closing = free[r] + _relative(push, rows, r) + _relative(shift, rows, r)
            target = POSITION_RATE * excess / dt
            total = max(rows.pseudo[r] + rows.mass[r] * (target - closing), 0.0)
            _apply(shift, masses, rows, r, total - rows.pseudo[r])
            rows.pseudo[r] = total


@njit(cache=True)
def collide(rows, count, velocities, accelerations, masses, restitution, rest_speed, dt, passes):
    """Step 0, on the velocities (n, 2) at the start of the step, in place: every row that meets
    within the step faster than the rest speed gets Newton's impulse J = -(1 + e)·u·m (u the
    relative normal velocity then), one row after another in canonical order, and again while
    any still meets (at most `passes` sweeps). Each impulse alone keeps momentum, and at e = 1
    energy, so a cluster of impacts does too. Impulses add into rows.hit."""
    rows.hit[:count] = 0.0
    for _ in range(passes):
        met = False
        for r in range(count):
            closing = _relative(velocities, rows, r)
            if closing >= -rest_speed:
                continue
            if rows.gap[r] > -(closing + 0.5 * dt * _relative(accelerations, rows, r)) * dt:
                continue   # still apart at the end of the step
            impulse = newton_impulse(closing, restitution, rows.mass[r])
            _apply(velocities, masses, rows, r, impulse)
            rows.hit[r] += impulse
            met = True
        if not met:
            return


@njit(cache=True)
def come_to_rest(rows, count, velocities, masses, iterations):
    """Step 4, on the final velocities (n, 2) in place: the rows that pressed leave at relative
    normal velocity 0 (their accumulated impulse may fall, never below 0). Each correction
    takes one row's relative normal velocity to 0, which only ever lowers kinetic energy:
    a resting contact does not bounce."""
    pressed = rows.impulse[:count] > 0.0
    for _ in range(iterations):
        for r in range(count):
            if pressed[r]:
                total = max(rows.impulse[r] - rows.mass[r] * _relative(velocities, rows, r), 0.0)
                _apply(velocities, masses, rows, r, total - rows.impulse[r])
                rows.impulse[r] = total
