"""The soft step: every contact of a step held by soft constraints over substeps (Box2D v3's solver).

Catto's "Solver2D" and Box2D v3 (solver.c, contact_solver.c) solve contacts in `SUBSTEPS`
substeps of h = dt/SUBSTEPS. Each substep

1. warm starts: applies each row's impulse of the substep before (the first, its share of the
   step before's: warmstart.py);
2. solves with a soft bias, in sweeps while they converge (SWEEPS): a row still apart may close
   no more than its gap in the substep (speculative, hard); an overlap between bodies is pushed
   out as a damped spring of CONTACT_HERTZ would push it (at most PUSH_OUT radii a second),
   softened by the spring's mass and impulse scales so that a row pressed by a pile gives like a
   stiff spring rather than fighting its neighbours (a static's row is hard); Coulomb friction
   within mu times the normal impulse;
3. moves the rows' bodies by what they solved (their gaps are then read from how far each
   body moved and turned since the rows were made, to first order as the rows' velocities are,
   not from a new narrow phase);
4. relaxes: solves again without the bias, so the push that took an overlap out does not
   stay in the velocity (a stack does not jitter). One sweep, as Box2D's relax, in every
   substep but the last, whose relax sweeps while they converge: what the earlier relaxes
   leave, the next substep's solve takes up, and the step ends with no push left in the
   velocities, which sleeping reads (engine/islands.py). Converged in every substep, the relax
   cost an awake pile much of its step and held the pyramids and stacks no better
   (docs/benchmarks.md). The solve still sweeps while it converges in every substep:
   at one sweep, a box held by friction on a slope crept.

Sweeping a pile's weight down contact by contact took the rigid solve as many sweeps as the pile
is high; the substeps carry it further each step, and the soft rows let the weight settle into
the pile as springs instead of being bounced between contacts (base-100 pyramid:
benchmarks/pyramid_stands.py).

As the rigid solve does, a substep works on the body's mean velocity w = v + ½·a·h + ½·P/m: an
impulse P spread over the substep moves the body by half of what it adds to the final velocity
v' = 2·w - v. So a free body's path is the exact parabola, and a box resting on the floor is
pressed by exactly m·g·dt a step and does not move. Impacts (solver.collide, Newton's impulse
with restitution) come before the soft step, which then holds what is left.

The step's result reaches the bodies as push and shift (solver.add_contact_motion), so that the
integration of every body followed by the contacts' share puts the rows' bodies exactly where
the substeps left them.
"""
import math

import numpy as np

from ..core.compiling import compiled, kernel
from .contact_row import block, couplings, inverses, kicked, load, relative, store

SWEEPS = 20        # a solve's sweeps at most: they run while each changes the impulses by less
SHRINK = 0.5       # than SHRINK times the sweep before (converging, not cycling over friction), to
TOLERANCE = 1e-9   # TOLERANCE of the largest impulse; so do a new row's (COLD_SWEEPS), which has
COLD_SWEEPS = 20   # no impulse of the step before to start from
SUBSTEPS = 4
CONTACT_HERTZ = 42.0    # the contact spring, at most a quarter of the substep rate (as Box2D's): a
                        # pile's weight gives each contact load·g/ω², 0.14 thousandths of a unit per
                        # body above it under g = 10 (the base-100 pyramid's top 0.32: at Box2D's
                        # 30 Hz, 0.62, and 888 boxes more than 0.5 below their start)
DAMPING_RATIO = 10.0    # heavily over-damped: an overlap is taken out without bouncing back
PUSH_OUT = 3.0          # radii a second: the fastest an overlap is pushed out


@kernel
def contact_hertz(h):
    """The contact spring's frequency for substeps of h: CONTACT_HERTZ, at most a quarter of the
    substep rate (a stiffer spring than the substeps can follow would ring)."""
    return min(CONTACT_HERTZ, 0.25 / h)


@kernel
def softness(hertz, zeta, h):
    """A damped spring of `hertz` as a soft constraint over a substep h: (bias rate, mass scale,
    impulse scale) (Box2D's b2MakeSoft)."""
    omega = 2.0 * math.pi * hertz
    a1 = 2.0 * zeta + h * omega
    a2 = h * omega * a1
    a3 = 1.0 / (1.0 + a2)
    return omega / a1, a2 * a3, a3


@compiled
def soft_step(rows, count, radii, lin, ang, accelerations, inverse_masses, inverse_inertias, friction, dt,
              keep, push_lin, push_ang, shift_lin, shift_ang, moved):
    """Solve rows[:count] over the step dt from the velocities (lin, ang) after impacts: set push
    and shift (n, 2) and their turns (n,) for the rows' bodies (see the module), and rows.impulse
    and rows.friction to each row's impulses summed over the step. keep: the fraction of its
    velocity a body keeps over the step (integrate.py). moved (n,) bool all False, as on return."""
    bodies = _gather(rows.i, rows.j, count, moved)
    k = bodies.shape[0]
    slot = np.empty(radii.shape[0], np.int64)   # only the rows' bodies' entries are read
    # per slot, as (linear (k, 2), turning (k,)): the velocity v at the substep's start, the mean
    # velocity w, the move d since the rows were made; and 1/m, 1/I
    v, w, d = (np.empty((k, 2)), np.empty(k)), (np.empty((k, 2)), np.empty(k)), (np.zeros((k, 2)), np.zeros(k))
    inverse = (inverse_masses[bodies], inverse_inertias[bodies])
    for q in range(k):
        i = bodies[q]
        slot[i] = q
        v[0][q, 0], v[0][q, 1], v[1][q] = keep * lin[i, 0], keep * lin[i, 1], keep * ang[i]
    h = dt / SUBSTEPS
    si, sj, spring = _row_springs(rows.i, rows.j, count, radii, slot, h)
    N, L, gap, mass, mass_t, partner = rows.normal, rows.lever, rows.gap, rows.mass, rows.mass_t, rows.partner
    n_acc, t_acc = rows.impulse[:count] / SUBSTEPS, rows.friction[:count] / SUBSTEPS
    cold = np.flatnonzero(n_acc == 0.0)   # rows without an impulse to start from
    n_sum, t_sum = np.zeros(count), np.zeros(count)
    everything = np.arange(count)
    pairs = _pair_couplings(si, sj, L, partner, count, inverse)
    goals = np.empty((count, 3))
    for substep in range(SUBSTEPS):
        for q in range(k):
            i = bodies[q]
            for axis in range(2):
                w[0][q, axis] = v[0][q, axis] + 0.5 * h * accelerations[i, axis]
            w[1][q] = v[1][q]
        _warm_start(si, sj, N, L, count, inverse, w, n_acc, t_acc)
        _goals(si, sj, N, L, gap, spring, d, count, h, True, goals)
        _sweeps(everything, cold, si, sj, N, L, goals, pairs, mass, mass_t, partner, inverse, w, n_acc, t_acc,
                friction, True, SWEEPS)
        for q in range(k):
            for axis in range(2):
                d[0][q, axis] += w[0][q, axis] * h
                v[0][q, axis] = 2.0 * w[0][q, axis] - v[0][q, axis]
            d[1][q] += w[1][q] * h
            v[1][q] = 2.0 * w[1][q] - v[1][q]
        _goals(si, sj, N, L, gap, spring, d, count, h, False, goals)
        _sweeps(everything, cold, si, sj, N, L, goals, pairs, mass, mass_t, partner, inverse, v, n_acc, t_acc,
                friction, False, SWEEPS if substep == SUBSTEPS - 1 else 1)
        cold = cold[:0]   # warm from the second substep on
        for r in range(count):   # (a loop: an operation on two whole arrays compiles numba's shape
            n_sum[r] += n_acc[r]   # check and its message's formatting: docs/design.md, compiling)
            t_sum[r] += t_acc[r]
    for r in range(count):
        rows.impulse[r], rows.friction[r], rows.pseudo[r] = n_sum[r], t_sum[r], 0.0
    for q in range(k):
        _as_push_and_shift(lin, ang, accelerations, keep, dt, bodies[q], q, v, d, push_lin, push_ang, shift_lin,
                           shift_ang)


@compiled
def _gather(I, J, count, moved):
    """The bodies of rows[:count], each once, in the order the rows first name them."""
    bodies = np.empty(2 * count, np.int64)
    k = 0
    for r in range(count):
        for i in (I[r], J[r]):
            if i >= 0 and not moved[i]:
                moved[i] = True
                bodies[k] = i
                k += 1
    for q in range(k):
        moved[bodies[q]] = False
    return bodies[:k]


@compiled
def _row_springs(I, J, count, radii, slot, h):
    """Each row's bodies as slots (sj -1 for a static) and its spring (count, 4): bias rate, mass
    scale, impulse scale (softness) and the fastest it pushes an overlap out. A static's row is
    hard, and pushes an overlap out at the rate of a spring twice as stiff (as Box2D's)."""
    si, sj, spring = np.empty(count, np.int64), np.empty(count, np.int64), np.empty((count, 4))
    hertz = contact_hertz(h)
    rate, scale, soften = softness(hertz, DAMPING_RATIO, h)
    static_rate = softness(2.0 * hertz, DAMPING_RATIO, h)[0]
    for r in range(count):
        i, j = I[r], J[r]
        si[r] = slot[i]
        if j < 0:
            sj[r] = -1
            spring[r, 0], spring[r, 1], spring[r, 2], spring[r, 3] = static_rate, 1.0, 0.0, PUSH_OUT * radii[i]
        else:
            sj[r] = slot[j]
            spring[r, 0], spring[r, 1], spring[r, 2], spring[r, 3] = rate, scale, soften, PUSH_OUT * min(radii[i],
                                                                                                      radii[j])
    return si, sj, spring


@kernel
def _warm_start(si, sj, N, L, count, inverse, w, n_acc, t_acc):
    """Each row's impulses of the substep before, spread over this one (half into w)."""
    for r in range(count):
        if n_acc[r] != 0.0 or t_acc[r] != 0.0:
            i, j = si[r], sj[r]
            vel = kicked(load(w[0], w[1], i, j), inverses(inverse[0], inverse[1], i, j), j, N[r, 0], N[r, 1],
                         L[r, 0], L[r, 1], L[r, 2], L[r, 3], 0.5 * n_acc[r], 0.5 * t_acc[r])
            store(w[0], w[1], i, j, vel)


@kernel
def _goals(si, sj, N, L, gap, spring, d, count, h, biased, goals):
    """goals (count, 3) <- each row's target closing speed and its softness (target, mass scale,
    impulse scale) for the sweeps to come, from its gap now (the bodies' moves d since the rows
    were made, which the sweeps do not change): still apart, it may close no more than its gap
    in the substep (hard); overlapping, the solve pushes the overlap out as the row's spring
    would, the relax only stops it closing (hard)."""
    for r in range(count):
        j = sj[r]
        moved = load(d[0], d[1], si[r], j)
        now = gap[r] + relative(moved, j, N[r, 0], N[r, 1], L[r, 0], L[r, 2])
        if now > 0.0:
            goals[r, 0], goals[r, 1], goals[r, 2] = -now / h, 1.0, 0.0
        elif not biased:
            goals[r, 0], goals[r, 1], goals[r, 2] = 0.0, 1.0, 0.0
        else:
            goals[r, 0], goals[r, 1], goals[r, 2] = min(-spring[r, 0] * now, spring[r, 3]), spring[r, 1], spring[r, 2]


@compiled
def _pair_couplings(si, sj, L, partner, count, inverse):
    """(count, 3): for the first row r of each two-point manifold (partner[r] = r + 1), the
    couplings k11, k22, k12 of its two points (contact_row.couplings), fixed over the step."""
    pairs = np.zeros((count, 3))
    for r in range(count - 1):
        s = r + 1
        if partner[r] == s:
            i, j = si[r], sj[r]
            m = inverses(inverse[0], inverse[1], i, j)
            pairs[r, 0], pairs[r, 1], pairs[r, 2] = couplings(m, j, L[r, 0], L[r, 2], L[s, 0], L[s, 2])
    return pairs


@kernel
def _sweeps(everything, cold, si, sj, N, L, goals, pairs, mass, mass_t, partner, inverse, vel, n_acc, t_acc,
            friction, biased, sweeps):
    """Sweeps (_sweep) over every row while they converge (at most `sweeps`), then over the rows
    `cold` without an impulse to start from (at most COLD_SWEEPS): each set until no sweep changes
    an accumulated impulse by more than TOLERANCE of the largest, or a sweep changes them by more
    than SHRINK of the sweep before."""
    for cold_rows in (False, True):
        which, most = (cold, COLD_SWEEPS) if cold_rows else (everything, sweeps)
        before = np.inf
        for _ in range(most if which.shape[0] > 0 else 0):
            change, largest = _sweep(which, si, sj, N, L, goals, pairs, mass, mass_t, partner, inverse, vel, n_acc,
                                     t_acc, friction, biased)
            if change <= TOLERANCE * largest or change > SHRINK * before:
                break
            before = change


@kernel
def _sweep(which, si, sj, N, L, goals, pairs, mass, mass_t, partner, inverse, vel, n_acc, t_acc, friction, biased):
    """One sweep over the rows `which` (ascending) on the slots' velocities vel: biased,
    the substep's solve on the mean velocities (an impulse moves them by half); else the relax
    on the final ones. The two points of a face on a face are solved together
    (contact_row.block), so a box landing flat does not start to turn. Returns the largest
    change of an accumulated impulse and the largest normal impulse."""
    half = 0.5 if biased else 1.0
    change, largest = 0.0, 0.0
    q = 0
    while q < which.shape[0]:
        r = which[q]
        i, j, nx, ny = si[r], sj[r], N[r, 0], N[r, 1]
        m = inverses(inverse[0], inverse[1], i, j)
        v = load(vel[0], vel[1], i, j)
        target, scale, soften = goals[r, 0], goals[r, 1], goals[r, 2]
        closing = relative(v, j, nx, ny, L[r, 0], L[r, 2])
        s = r + 1
        if partner[r] == s and q + 1 < which.shape[0] and which[q + 1] == s:
            target_s, scale_s, soften_s = goals[s, 0], goals[s, 1], goals[s, 2]
            k11, k22, k12 = half * pairs[r, 0], half * pairs[r, 1], half * pairs[r, 2]
            a1, a2 = n_acc[r], n_acc[s]
            found, x1, x2 = block(k11, k22, k12,
                                  scale * (closing - target) - (1.0 - soften) * (k11 * a1 + k12 * a2),
                                  scale_s * (relative(v, j, nx, ny, L[s, 0], L[s, 2]) - target_s)
                                  - (1.0 - soften_s) * (k12 * a1 + k22 * a2))
            if found:
                v = kicked(v, m, j, nx, ny, L[r, 0], L[r, 1], L[r, 2], L[r, 3], half * (x1 - a1), 0.0)
                v = kicked(v, m, j, nx, ny, L[s, 0], L[s, 1], L[s, 2], L[s, 3], half * (x2 - a2), 0.0)
                n_acc[r], n_acc[s] = x1, x2
                change, largest = max(change, abs(x1 - a1), abs(x2 - a2)), max(largest, x1, x2)
                if friction > 0.0:
                    for p in (r, s):
                        before = t_acc[p]
                        v, t_acc[p] = _friction(v, m, j, nx, ny, L[p, 0], L[p, 1], L[p, 2], L[p, 3], mass_t[p], half,
                                                friction * n_acc[p], before)
                        change = max(change, abs(t_acc[p] - before))
                store(vel[0], vel[1], i, j, v)
                q += 2
                continue
        total = max(n_acc[r] - mass[r] * scale * (closing - target) / half - soften * n_acc[r], 0.0)
        v = kicked(v, m, j, nx, ny, L[r, 0], L[r, 1], L[r, 2], L[r, 3], half * (total - n_acc[r]), 0.0)
        change, largest = max(change, abs(total - n_acc[r])), max(largest, total)
        n_acc[r] = total
        if friction > 0.0:
            before = t_acc[r]
            v, t_acc[r] = _friction(v, m, j, nx, ny, L[r, 0], L[r, 1], L[r, 2], L[r, 3], mass_t[r], half,
                                    friction * total, before)
            change = max(change, abs(t_acc[r] - before))
        store(vel[0], vel[1], i, j, v)
        q += 1
    return change, largest


@kernel
def _friction(v, m, j, nx, ny, l0, l1, l2, l3, mass_t, half, bound, accumulated):
    """Coulomb friction at a row on the pair's loaded velocities v: the tangential impulse that
    stops its sliding, its total kept within ±bound. Returns (v, the new total)."""
    sliding = relative(v, j, -ny, nx, l1, l3)
    spread = min(max(accumulated - mass_t * sliding / half, -bound), bound)
    return kicked(v, m, j, nx, ny, l0, l1, l2, l3, 0.0, half * (spread - accumulated)), spread


@kernel
def _as_push_and_shift(lin, ang, accelerations, keep, dt, i, q, v, d, push_lin, push_ang, shift_lin, shift_ang):
    """Body i's end velocity and move (slot q of v and d) as the contacts' share of the step: the
    integration gives keep·v0 + a·dt and keep·v0·dt + ½·a·dt², add_contact_motion adds 2·push to
    the velocity and (push + shift)·dt to the position."""
    for axis in range(2):
        push = 0.5 * (v[0][q, axis] - keep * lin[i, axis] - accelerations[i, axis] * dt)
        push_lin[i, axis] = push
        shift_lin[i, axis] = d[0][q, axis] / dt - keep * lin[i, axis] - 0.5 * accelerations[i, axis] * dt - push
    turn = 0.5 * (v[1][q] - keep * ang[i])
    push_ang[i] = turn
    shift_ang[i] = d[1][q] / dt - keep * ang[i] - turn
