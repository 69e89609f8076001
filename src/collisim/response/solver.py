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

# The loops below read each row's fields into plain numbers and hand only numbers and the
# per-body arrays to the small functions they call. A call that is handed the Rows tuple itself
# (16 arrays) costs about half a microsecond whatever it does: 20 to 80 times its arithmetic.


@njit(cache=True, inline="always")
def relative(lin, ang, i, j, dx, dy, lever_i, lever_j):
    """(v_j - v_i) along (dx, dy) at a contact point of bodies i and j (j < 0: a wall, which does
    not move), for per-body vectors. A point at arm a moves at v + ω × a, whose part along d is
    v·d + ω·(a × d): the point's lever about each centre (lever_i, lever_j)."""
    rel = -(lin[i, 0] * dx + lin[i, 1] * dy + ang[i] * lever_i)
    if j >= 0:
        rel += lin[j, 0] * dx + lin[j, 1] * dy + ang[j] * lever_j
    return rel


@njit(cache=True, inline="always")
def apply(lin, ang, masses, inertias, i, j, nx, ny, l0, l1, l2, l3, normal_impulse, tangent_impulse):
    """Change the per-body vectors by impulses along a row's normal (nx, ny) and tangent
    (-ny, nx), at its point (levers l0..l3 as Rows.lever): i pushed back, j on."""
    px, py = normal_impulse * nx - tangent_impulse * ny, normal_impulse * ny + tangent_impulse * nx
    lin[i, 0] -= px / masses[i]
    lin[i, 1] -= py / masses[i]
    ang[i] -= (normal_impulse * l0 + tangent_impulse * l1) / inertias[i]
    if j >= 0:
        lin[j, 0] += px / masses[j]
        lin[j, 1] += py / masses[j]
        ang[j] += (normal_impulse * l2 + tangent_impulse * l3) / inertias[j]


@njit(cache=True, inline="always")
def _friction(lin, ang, masses, inertias, i, j, nx, ny, l0, l1, l2, l3, mass_t, limit, accumulated):
    """Coulomb friction at a row on velocities (lin, ang): the tangential impulse that stops its
    sliding, with the row's accumulated friction impulse kept within ±limit. Returns the new
    accumulated impulse (the impulse applied is its change)."""
    sliding = relative(lin, ang, i, j, -ny, nx, l1, l3)
    total = min(max(accumulated - mass_t * sliding, -limit), limit)
    apply(lin, ang, masses, inertias, i, j, nx, ny, l0, l1, l2, l3, 0.0, total - accumulated)
    return total


@njit(cache=True, inline="always")
def _meets(lin, ang, accelerations, i, j, nx, ny, lever_i, lever_j, gap, dt, rest_speed):
    """A row's closing speed if it meets within the step faster than the rest speed, else 0."""
    closing = relative(lin, ang, i, j, nx, ny, lever_i, lever_j)
    if closing >= -rest_speed:
        return 0.0
    pull = (accelerations[j, 0] * nx + accelerations[j, 1] * ny) if j >= 0 else 0.0
    pull -= accelerations[i, 0] * nx + accelerations[i, 1] * ny
    if gap > -(closing + 0.5 * dt * pull) * dt:
        return 0.0   # still apart at the end of the step
    return closing


@njit(cache=True, inline="always")
def _coupling(masses, inertias, i, j, lever_r_i, lever_s_i, lever_r_j, lever_s_j):
    """The normal velocity change at one point of a manifold per unit normal impulse at another
    (or the same) point, from their normal levers about each centre."""
    k = 1.0 / masses[i] + lever_r_i * lever_s_i / inertias[i]
    if j >= 0:
        k += 1.0 / masses[j] + lever_r_j * lever_s_j / inertias[j]
    return k


@njit(cache=True, inline="always")
def _couplings(masses, inertias, i, j, lr0, lr2, ls0, ls2):
    """k11, k22, k12 of the two points r and s of a manifold (same bodies and normal), from their
    normal levers (lr0, lr2) and (ls0, ls2)."""
    k11 = _coupling(masses, inertias, i, j, lr0, lr0, lr2, lr2)
    k22 = _coupling(masses, inertias, i, j, ls0, ls0, ls2, ls2)
    k12 = _coupling(masses, inertias, i, j, lr0, ls0, lr2, ls2)
    return k11, k22, k12


@njit(cache=True, inline="always")
def _block(k11, k22, k12, b1, b2):
    """The two points of a face on a face solved together, as Box2D's block solver does: the
    accumulated impulses x >= 0 that bring both closing speeds to their targets, or one of them
    with the other left separating, or none; b1, b2 the closing speeds less the targets with no
    impulse, k the couplings. Solved one point after the other, a resting box would tip a
    little each sweep, and a stack of boxes would lean and walk. Returns (found, x1, x2)."""
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
    return found, x1, x2


@njit(cache=True, inline="always")
def _together(k11, k22, k12, u1, u2, restitution):
    """Both points of a two-point manifold meeting at closing speeds u1, u2: the impulses that give
    each -e times its closing speed at once. Returns (possible, j1, j2): not possible if that
    would need a pull."""
    det = k11 * k22 - k12 * k12
    if det <= 1e-12 * k11 * k22:
        return False, 0.0, 0.0
    b1, b2 = -(1.0 + restitution) * u1, -(1.0 + restitution) * u2
    j1, j2 = (k22 * b1 - k12 * b2) / det, (k11 * b2 - k12 * b1) / det
    return j1 >= 0.0 and j2 >= 0.0, j1, j2


@njit(cache=True)
def collide(rows, count, lin, ang, accelerations, masses, inertias, restitution, friction, rest_speed, dt, passes):
    """Impacts, on the velocities at the start of the step (lin (n, 2), ang (n,)) in place: see the
    module. Normal impulses add into rows.hit."""
    I, J, N, L, gap, hit = rows.i, rows.j, rows.normal, rows.lever, rows.gap, rows.hit
    partner, mass, mass_t = rows.partner, rows.mass, rows.mass_t
    hit[:count] = 0.0
    slid = np.zeros(count)   # the friction impulse of each row's impacts
    for _ in range(passes):
        met = False
        r = 0
        while r < count:
            i, j, nx, ny = I[r], J[r], N[r, 0], N[r, 1]
            closing = _meets(lin, ang, accelerations, i, j, nx, ny, L[r, 0], L[r, 2], gap[r], dt, rest_speed)
            if partner[r] == r + 1:
                s = r + 1
                other = _meets(lin, ang, accelerations, i, j, nx, ny, L[s, 0], L[s, 2], gap[s], dt, rest_speed)
                if closing < 0.0 and other < 0.0:
                    k11, k22, k12 = _couplings(masses, inertias, i, j, L[r, 0], L[r, 2], L[s, 0], L[s, 2])
                    possible, j1, j2 = _together(k11, k22, k12, closing, other, restitution)
                    if possible:
                        apply(lin, ang, masses, inertias, i, j, nx, ny, L[r, 0], L[r, 1], L[r, 2], L[r, 3], j1, 0.0)
                        apply(lin, ang, masses, inertias, i, j, nx, ny, L[s, 0], L[s, 1], L[s, 2], L[s, 3], j2, 0.0)
                        hit[r] += j1
                        hit[s] += j2
                        if friction > 0.0:
                            for q in (r, s):
                                slid[q] = _friction(lin, ang, masses, inertias, i, j, nx, ny, L[q, 0], L[q, 1],
                                                    L[q, 2], L[q, 3], mass_t[q], friction * hit[q], slid[q])
                        met = True
                        r += 2
                        continue
            if closing < 0.0:
                impulse = newton_impulse(closing, restitution, mass[r])
                apply(lin, ang, masses, inertias, i, j, nx, ny, L[r, 0], L[r, 1], L[r, 2], L[r, 3], impulse, 0.0)
                hit[r] += impulse
                if friction > 0.0:
                    slid[r] = _friction(lin, ang, masses, inertias, i, j, nx, ny, L[r, 0], L[r, 1], L[r, 2], L[r, 3],
                                        mass_t[r], friction * hit[r], slid[r])
                met = True
            r += 1
        if not met:
            return


@njit(cache=True, inline="always")
def _closing(i, j, nx, ny, lever_i, lever_j, lin, ang, push_lin, push_ang):
    """Relative velocity along (nx, ny) of the sum of two per-body vectors, each taken apart."""
    return (relative(lin, ang, i, j, nx, ny, lever_i, lever_j)
            + relative(push_lin, push_ang, i, j, nx, ny, lever_i, lever_j))


@njit(cache=True)
def solve_velocities(rows, count, lin, ang, accelerations, masses, inertias, friction, dt, iterations,
                     push_lin, push_ang):
    """Steps 1 and 2, from the velocities (lin, ang): the contact impulses rows.impulse and
    rows.friction, and the change they make to each body's mean velocity, push_lin (n, 2) and
    push_ang (n,) (zeroed here; the mean velocity is lin + ½·a·dt + push)."""
    push_lin[:] = 0.0
    push_ang[:] = 0.0
    mean_lin = lin + 0.5 * dt * accelerations
    I, J, N, L, impulses, frictions = rows.i, rows.j, rows.normal, rows.lever, rows.impulse, rows.friction
    gap, partner, mass, mass_t = rows.gap, rows.partner, rows.mass, rows.mass_t
    for r in range(count):
        if impulses[r] != 0.0 or frictions[r] != 0.0:
            apply(push_lin, push_ang, masses, inertias, I[r], J[r], N[r, 0], N[r, 1], L[r, 0], L[r, 1], L[r, 2],
                  L[r, 3], 0.5 * impulses[r], 0.5 * frictions[r])
    for _ in range(iterations):   # a sweep that changes nothing ends the solve: the next would too
        changed = False
        for r in range(count):
            if friction > 0.0:   # friction first, within what the normal impulse allowed last sweep
                i, j, nx, ny = I[r], J[r], N[r, 0], N[r, 1]
                sliding = _closing(i, j, -ny, nx, L[r, 1], L[r, 3], mean_lin, ang, push_lin, push_ang)
                limit = friction * impulses[r]
                spread = min(max(frictions[r] - 2.0 * mass_t[r] * sliding, -limit), limit)
                if spread != frictions[r]:
                    apply(push_lin, push_ang, masses, inertias, i, j, nx, ny, L[r, 0], L[r, 1], L[r, 2], L[r, 3],
                          0.0, 0.5 * (spread - frictions[r]))
                    frictions[r] = spread
                    changed = True
        r = 0
        while r < count:
            i, j, nx, ny = I[r], J[r], N[r, 0], N[r, 1]
            closing = _closing(i, j, nx, ny, L[r, 0], L[r, 2], mean_lin, ang, push_lin, push_ang)
            target = -max(gap[r], 0.0) / dt
            if partner[r] == r + 1:
                s = r + 1
                second = _closing(i, j, nx, ny, L[s, 0], L[s, 2], mean_lin, ang, push_lin, push_ang)
                k11, k22, k12 = _couplings(masses, inertias, i, j, L[r, 0], L[r, 2], L[s, 0], L[s, 2])
                k11, k22, k12 = 0.5 * k11, 0.5 * k22, 0.5 * k12   # an impulse moves the mean velocity by half
                a1, a2, target2 = impulses[r], impulses[s], -max(gap[s], 0.0) / dt
                found, x1, x2 = _block(k11, k22, k12, closing - target - (k11 * a1 + k12 * a2),
                                       second - target2 - (k12 * a1 + k22 * a2))
                if found:
                    apply(push_lin, push_ang, masses, inertias, i, j, nx, ny, L[r, 0], L[r, 1], L[r, 2], L[r, 3],
                          0.5 * (x1 - a1), 0.0)
                    apply(push_lin, push_ang, masses, inertias, i, j, nx, ny, L[s, 0], L[s, 1], L[s, 2], L[s, 3],
                          0.5 * (x2 - a2), 0.0)
                    impulses[r], impulses[s] = x1, x2
                    changed = changed or (a1, a2) != (x1, x2)
                    r += 2
                    continue
            total = max(impulses[r] + 2.0 * mass[r] * (target - closing), 0.0)
            if total != impulses[r]:
                apply(push_lin, push_ang, masses, inertias, i, j, nx, ny, L[r, 0], L[r, 1], L[r, 2], L[r, 3],
                      0.5 * (total - impulses[r]), 0.0)
                impulses[r] = total
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
    I, J, N, L, pseudo = rows.i, rows.j, rows.normal, rows.lever, rows.pseudo
    gap, slop, mass = rows.gap, rows.slop, rows.mass
    for _ in range(iterations):
        changed = False
        for r in range(count):
            excess = -gap[r] - slop[r]
            if excess <= 0.0:
                continue
            i, j, nx, ny = I[r], J[r], N[r, 0], N[r, 1]
            closing = (_closing(i, j, nx, ny, L[r, 0], L[r, 2], mean_lin, ang, push_lin, push_ang)
                       + relative(shift_lin, shift_ang, i, j, nx, ny, L[r, 0], L[r, 2]))
            total = max(pseudo[r] + mass[r] * (POSITION_RATE * excess / dt - closing), 0.0)
            if total != pseudo[r]:
                apply(shift_lin, shift_ang, masses, inertias, i, j, nx, ny, L[r, 0], L[r, 1], L[r, 2], L[r, 3],
                      total - pseudo[r], 0.0)
                pseudo[r] = total
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
    I, J, N, L, impulses, frictions = rows.i, rows.j, rows.normal, rows.lever, rows.impulse, rows.friction
    mass, mass_t = rows.mass, rows.mass_t
    for _ in range(iterations):   # a sweep that changes nothing ends it: the next would too
        changed = False
        for r in range(count):
            if pressed[r]:
                i, j, nx, ny = I[r], J[r], N[r, 0], N[r, 1]
                total = max(impulses[r] - mass[r] * relative(lin, ang, i, j, nx, ny, L[r, 0], L[r, 2]), 0.0)
                if total != impulses[r]:
                    apply(lin, ang, masses, inertias, i, j, nx, ny, L[r, 0], L[r, 1], L[r, 2], L[r, 3],
                          total - impulses[r], 0.0)
                    impulses[r] = total
                    changed = True
                if friction > 0.0:
                    slid = _friction(lin, ang, masses, inertias, i, j, nx, ny, L[r, 0], L[r, 1], L[r, 2], L[r, 3],
                                     mass_t[r], friction * total, frictions[r])
                    changed = changed or slid != frictions[r]
                    frictions[r] = slid
        if not changed:
            break
