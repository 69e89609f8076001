"""The contact solver: every contact of a step solved together, by sequential impulses.

A body's step from p with velocity v under a constant acceleration a is the parabola
p' = p + w·dt with the mean velocity w = v + ½·a·dt, ending with v' = v + a·dt. A contact
impulse P is taken as spread evenly over the step (as a resting contact's force is): it adds
½·P/m to the mean velocity and P/m to the final one (and likewise for turning, with the moment
of inertia). So a ball resting on the floor is pressed by exactly P = m·g·dt a step, ends the
step where it started, and at rest — no micro-bounce, and the floor's pressure is its weight
(wall events log P).

First, **impacts** (`collide`): rows that meet within the step faster than the rest speed get
Newton's impulse with restitution e (and Coulomb friction), one after another while any still
meets — the video's two-body response, exact for an isolated pair; the two points of a face
meeting a face get theirs together (so a box landing flat does not start to spin). Every
impulse alone keeps momentum and, at e = 1, energy, so any cluster of impacts does too.

What is left — contacts slower than the rest speed, under gravity — is held by the solve, on the
rows of response/rows.py:

1. **warm start**: each row starts from its contact's impulses of the step before (warmstart.py);
2. **velocities** (`iterations` sweeps in row order): the mean relative normal velocity of each
   row may not close more than its gap in the step, w_n >= -max(gap, 0)/dt, with the accumulated
   normal impulse kept >= 0 (contacts push, never pull) and the friction impulse within
   μ times it. An impact left over stops where the bodies meet instead of sinking one into the
   other, and a pile passes its weight down to the floor;
3. **positions** (split impulse, as Box2D and Chipmunk do): an overlap beyond the row's slop is
   removed, a fraction POSITION_RATE of it a step, by pseudo-velocities that move positions and
   are then forgotten — correcting an overlap adds no kinetic energy;
4. **rest**, on the final velocities: the rows that pressed leave at relative normal velocity 0
   (and friction takes out what sliding it can) — a resting contact does not bounce.

Per-body vectors are (lin (n, 2), ang (n,)): a velocity and a turning rate, or their changes.
"""
import numpy as np
from numba import njit

from .impulse import newton_impulse

POSITION_RATE = 0.2   # the fraction of an overlap (beyond the slop) removed per step
NORMAL, TANGENT = 0, 1


@njit(cache=True)
def relative(lin, ang, rows, r, along):
    """(v_j - v_i) at row r's point, along its normal (along = 0) or its tangent (1), for per-body
    vectors; a wall does not move. A point at arm a moves at v + ω × a, whose part along n is
    v·n + ω·(a × n): the row's lever."""
    i, j = rows.i[r], rows.j[r]
    nx, ny = rows.normal[r, 0], rows.normal[r, 1]
    dx, dy = (nx, ny) if along == 0 else (-ny, nx)
    rel = -(lin[i, 0] * dx + lin[i, 1] * dy + ang[i] * rows.lever[r, along])
    if j >= 0:
        rel += lin[j, 0] * dx + lin[j, 1] * dy + ang[j] * rows.lever[r, 2 + along]
    return rel


@njit(cache=True)
def _normal(rows, r):
    return rows.normal[r, 0], rows.normal[r, 1]


@njit(cache=True)
def _tangent(rows, r):
    return -rows.normal[r, 1], rows.normal[r, 0]


@njit(cache=True)
def apply(lin, ang, masses, inertias, rows, r, normal_impulse, tangent_impulse):
    """Change the per-body vectors by impulses along row r's normal and tangent, at its point
    (i pushed back, j on)."""
    nx, ny = _normal(rows, r)
    px, py = normal_impulse * nx - tangent_impulse * ny, normal_impulse * ny + tangent_impulse * nx
    i, j, lever = rows.i[r], rows.j[r], rows.lever[r]
    lin[i, 0] -= px / masses[i]
    lin[i, 1] -= py / masses[i]
    ang[i] -= (normal_impulse * lever[0] + tangent_impulse * lever[1]) / inertias[i]
    if j >= 0:
        lin[j, 0] += px / masses[j]
        lin[j, 1] += py / masses[j]
        ang[j] += (normal_impulse * lever[2] + tangent_impulse * lever[3]) / inertias[j]


@njit(cache=True)
def _friction(rows, r, friction, limit, lin, ang, masses, inertias, accumulated):
    """Coulomb friction at row r on velocities (lin, ang): the tangential impulse that stops its
    sliding, with accumulated[r] + it kept within ±limit. Returns the impulse applied."""
    if friction <= 0.0:
        return 0.0
    sliding = relative(lin, ang, rows, r, TANGENT)
    total = min(max(accumulated[r] - rows.mass_t[r] * sliding, -limit), limit)
    impulse = total - accumulated[r]
    apply(lin, ang, masses, inertias, rows, r, 0.0, impulse)
    accumulated[r] = total
    return impulse


@njit(cache=True)
def _meets(rows, r, lin, ang, accelerations, dt, rest_speed):
    """Row r's closing speed if it meets within the step faster than the rest speed, else 0."""
    nx, ny = _normal(rows, r)
    closing = relative(lin, ang, rows, r, NORMAL)
    if closing >= -rest_speed:
        return 0.0
    pull = (accelerations[rows.j[r], 0] * nx + accelerations[rows.j[r], 1] * ny) if rows.j[r] >= 0 else 0.0
    pull -= accelerations[rows.i[r], 0] * nx + accelerations[rows.i[r], 1] * ny
    if rows.gap[r] > -(closing + 0.5 * dt * pull) * dt:
        return 0.0   # still apart at the end of the step
    return closing


@njit(cache=True)
def _coupling(rows, r, s, masses, inertias):
    """The normal velocity change at row r's point per unit normal impulse at row s's (same bodies)."""
    i, j = rows.i[r], rows.j[r]   # the two points of a manifold share bodies and normal
    k = 1.0 / masses[i] + rows.lever[r, 0] * rows.lever[s, 0] / inertias[i]
    if j >= 0:
        k += 1.0 / masses[j] + rows.lever[r, 2] * rows.lever[s, 2] / inertias[j]
    return k


@njit(cache=True)
def _block(rows, r, closing1, closing2, target1, target2, spread, accumulated, lin, ang, masses, inertias):
    """The two points of a face on a face (rows r, r + 1) solved together, as Box2D's block solver
    does: the accumulated impulses x >= 0 that bring both closing speeds to their targets, or one
    of them with the other left separating, or none. Solved one point after the other, a
    resting box would tip a little each sweep, and a stack of boxes would lean and walk. spread
    is ½ in the velocity solve (an impulse moves the mean velocity by half), 1 elsewhere.
    Returns False (nothing applied) if no case holds."""
    s = r + 1
    k11 = spread * _coupling(rows, r, r, masses, inertias)
    k22 = spread * _coupling(rows, s, s, masses, inertias)
    k12 = spread * _coupling(rows, r, s, masses, inertias)
    a1, a2 = accumulated[r], accumulated[s]
    b1 = closing1 - target1 - (k11 * a1 + k12 * a2)    # the closing speeds less the targets with no impulse
    b2 = closing2 - target2 - (k12 * a1 + k22 * a2)
    det = k11 * k22 - k12 * k12
    x1, x2, found = 0.0, 0.0, False
    if det > 1e-12 * k11 * k22:
        x1, x2 = (-k22 * b1 + k12 * b2) / det, (k12 * b1 - k11 * b2) / det
        found = x1 >= 0.0 and x2 >= 0.0
    if not found:
        x1, x2 = -b1 / k11, 0.0
        found = x1 >= 0.0 and k12 * x1 + b2 >= 0.0
    if not found:
        x1, x2 = 0.0, -b2 / k22
        found = x2 >= 0.0 and k12 * x2 + b1 >= 0.0
    if not found:
        x1, x2 = 0.0, 0.0
        found = b1 >= 0.0 and b2 >= 0.0
    if found:
        apply(lin, ang, masses, inertias, rows, r, spread * (x1 - a1), 0.0)
        apply(lin, ang, masses, inertias, rows, s, spread * (x2 - a2), 0.0)
        accumulated[r], accumulated[s] = x1, x2
    return found


@njit(cache=True)
def _together(rows, r, u1, u2, restitution, masses, inertias, lin, ang):
    """Both points of a two-point manifold (rows r, r + 1) meeting: the impulses that give each
    -e times its closing speed at once. False (nothing applied) if that would need a pull."""
    s = r + 1
    k11, k22 = _coupling(rows, r, r, masses, inertias), _coupling(rows, s, s, masses, inertias)
    k12 = _coupling(rows, r, s, masses, inertias)
    det = k11 * k22 - k12 * k12
    if det <= 1e-12 * k11 * k22:
        return False
    b1, b2 = -(1.0 + restitution) * u1, -(1.0 + restitution) * u2
    j1, j2 = (k22 * b1 - k12 * b2) / det, (k11 * b2 - k12 * b1) / det
    if j1 < 0.0 or j2 < 0.0:
        return False
    apply(lin, ang, masses, inertias, rows, r, j1, 0.0)
    apply(lin, ang, masses, inertias, rows, s, j2, 0.0)
    rows.hit[r] += j1
    rows.hit[s] += j2
    return True


@njit(cache=True)
def collide(rows, count, lin, ang, accelerations, masses, inertias, restitution, friction, rest_speed, dt, passes):
    """Impacts, on the velocities at the start of the step (lin (n, 2), ang (n,)) in place: see the
    module. Normal impulses add into rows.hit."""
    rows.hit[:count] = 0.0
    slid = np.zeros(count)   # the friction impulse of each row's impacts
    for _ in range(passes):
        met = False
        r = 0
        while r < count:
            closing = _meets(rows, r, lin, ang, accelerations, dt, rest_speed)
            paired = rows.partner[r] == r + 1
            if paired:
                other = _meets(rows, r + 1, lin, ang, accelerations, dt, rest_speed)
                if closing < 0.0 and other < 0.0 and _together(rows, r, closing, other, restitution, masses,
                                                               inertias, lin, ang):
                    for s in (r, r + 1):
                        _friction(rows, s, friction, friction * rows.hit[s], lin, ang, masses, inertias, slid)
                    met = True
                    r += 2
                    continue
            if closing < 0.0:
                impulse = newton_impulse(closing, restitution, rows.mass[r])
                apply(lin, ang, masses, inertias, rows, r, impulse, 0.0)
                rows.hit[r] += impulse
                _friction(rows, r, friction, friction * rows.hit[r], lin, ang, masses, inertias, slid)
                met = True
            r += 1
        if not met:
            return


@njit(cache=True)
def _mean_closing(rows, r, mean_lin, ang, push_lin, push_ang):
    return relative(mean_lin, ang, rows, r, NORMAL) + relative(push_lin, push_ang, rows, r, NORMAL)


@njit(cache=True)
def solve_velocities(rows, count, lin, ang, accelerations, masses, inertias, friction, dt, iterations,
                     push_lin, push_ang):
    """Steps 1 and 2, from the velocities (lin, ang): the contact impulses rows.impulse and
    rows.friction, and the change they make to each body's mean velocity, push_lin (n, 2) and
    push_ang (n,) (zeroed here; the mean velocity is lin + ½·a·dt + push)."""
    push_lin[:] = 0.0
    push_ang[:] = 0.0
    mean_lin = lin + 0.5 * dt * accelerations
    for r in range(count):
        if rows.impulse[r] != 0.0 or rows.friction[r] != 0.0:
            apply(push_lin, push_ang, masses, inertias, rows, r, 0.5 * rows.impulse[r], 0.5 * rows.friction[r])
    for _ in range(iterations):   # a sweep that changes nothing ends the solve: the next would too
        changed = False
        for r in range(count):
            if friction > 0.0:   # friction first, within what the normal impulse allowed last sweep
                sliding = relative(mean_lin, ang, rows, r, TANGENT) + relative(push_lin, push_ang, rows, r, TANGENT)
                limit = friction * rows.impulse[r]
                spread = min(max(rows.friction[r] - 2.0 * rows.mass_t[r] * sliding, -limit), limit)
                if spread != rows.friction[r]:
                    apply(push_lin, push_ang, masses, inertias, rows, r, 0.0, 0.5 * (spread - rows.friction[r]))
                    rows.friction[r] = spread
                    changed = True
        r = 0
        while r < count:
            closing = _mean_closing(rows, r, mean_lin, ang, push_lin, push_ang)
            target = -max(rows.gap[r], 0.0) / dt
            if rows.partner[r] == r + 1:
                second = _mean_closing(rows, r + 1, mean_lin, ang, push_lin, push_ang)
                before = (rows.impulse[r], rows.impulse[r + 1])
                if _block(rows, r, closing, second, target, -max(rows.gap[r + 1], 0.0) / dt, 0.5, rows.impulse,
                          push_lin, push_ang, masses, inertias):
                    changed = changed or before != (rows.impulse[r], rows.impulse[r + 1])
                    r += 2
                    continue
            total = max(rows.impulse[r] + 2.0 * rows.mass[r] * (target - closing), 0.0)
            if total != rows.impulse[r]:
                apply(push_lin, push_ang, masses, inertias, rows, r, 0.5 * (total - rows.impulse[r]), 0.0)
                rows.impulse[r] = total
                changed = True
            r += 1
        if not changed:
            break


@njit(cache=True)
def solve_positions(rows, count, lin, ang, accelerations, masses, inertias, dt, iterations, push_lin, push_ang,
                    shift_lin, shift_ang):
    """Step 3: pseudo-velocities shift_lin (n, 2), shift_ang (n,) (zeroed here) that take overlaps
    beyond the slop out at POSITION_RATE a step, given the solved mean velocities."""
    shift_lin[:] = 0.0
    shift_ang[:] = 0.0
    rows.pseudo[:count] = 0.0
    mean_lin = lin + 0.5 * dt * accelerations
    for _ in range(iterations):
        changed = False
        for r in range(count):
            excess = -rows.gap[r] - rows.slop[r]
            if excess <= 0.0:
                continue
            closing = (relative(mean_lin, ang, rows, r, NORMAL) + relative(push_lin, push_ang, rows, r, NORMAL)
                       + relative(shift_lin, shift_ang, rows, r, NORMAL))
            total = max(rows.pseudo[r] + rows.mass[r] * (POSITION_RATE * excess / dt - closing), 0.0)
            if total != rows.pseudo[r]:
                apply(shift_lin, shift_ang, masses, inertias, rows, r, total - rows.pseudo[r], 0.0)
                rows.pseudo[r] = total
                changed = True
        if not changed:
            break


@njit(cache=True)
def come_to_rest(rows, count, lin, ang, masses, inertias, friction, iterations):
    """Step 4, on the final velocities (lin, ang) in place: the rows that pressed leave at relative
    normal velocity 0 (their accumulated impulse may fall, never below 0), and friction takes
    out what sliding it can. Each correction takes one row's relative velocity toward 0, which
    only ever lowers kinetic energy: a resting contact does not bounce."""
    pressed = rows.impulse[:count] > 0.0
    if not pressed.any():
        return
    for _ in range(iterations):
        for r in range(count):
            if pressed[r]:
                total = max(rows.impulse[r] - rows.mass[r] * relative(lin, ang, rows, r, NORMAL), 0.0)
                apply(lin, ang, masses, inertias, rows, r, total - rows.impulse[r], 0.0)
                rows.impulse[r] = total
                _friction(rows, r, friction, friction * total, lin, ang, masses, inertias, rows.friction)
