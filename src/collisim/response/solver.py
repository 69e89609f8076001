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
impulse alone keeps momentum and, at e = 1, energy, so any cluster of impacts does too. With
e = 0 a contact with a static that is still apart arrives instead: the solve below brings the
body onto the static, exactly, by the step's end (collide).

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

**Held from below** (hold.py): where the sweeps cannot carry a heavy body's weight down a stack
of much lighter ones, the rows left short are held once more from the ground up, and the frame
is flagged approximate.

Per-body vectors are (lin (n, 2), ang (n,)): a velocity and a turning rate, or their changes.
Bodies' inertia comes as inverse_masses (n,) and inverse_inertias (n,): 1/m and 1/I.
"""
import numpy as np

from ..core.compiling import compiled, inlined, kernel
from .contact_row import (block, couplings, friction_kick, inverses, kicked, load, load_mean, meets, relative,
                          store, together, zero_bodies)
from .hold import hold_from_below
from .impulse import newton_impulse

POSITION_RATE = 0.2   # the fraction of an overlap (beyond the slop) removed per step
# A pass's sweeps end when the largest change a sweep makes to any accumulated impulse is at most
# this share of the largest impulse (or after its `iterations`): the solve has converged, and
# the next sweeps would change velocities by far less than rounding shows in a frame. Warm
# started (warmstart.py), a frictionless pile at rest converges in one or two sweeps instead of
# twenty.
TOLERANCE = 1e-9
# With friction the sweeps need not converge: Gauss-Seidel over Coulomb's cones can cycle, a
# contact's friction and normal impulses trading the same amount back and forth at every sweep
# (on the polygons scene's pile the change levels off anywhere from 1e-9 to 3e-5 of the largest
# impulse and stays there for every sweep). So with friction, after STALL_AFTER sweeps (pymunk's
# default count), the velocity sweeps also end at the first that changes the impulses by more
# than STALL times the sweep before: the solve is cycling, not converging, and more sweeps buy
# nothing. Not sooner: a converging solve's change shrinks unevenly (a box held by friction on a
# slope: 2.2e-2, 5.2e-3, 4.8e-3, 1.8e-3 of the largest impulse over sweeps 4 to 7), and stopped at
# its seventh sweep the box crept 2e-5 down the slope in a second. Measured on the stack of six
# boxes (30 s, e = 0, mu = 0.5; the largest distance from the start over the run): without this
# rule 8.8e-3 sideways and 6.5e-3 down, ending still to 1.3e-3 units/s; with it 2.6e-3 and
# 5.1e-3, still to 3e-9 units/s. The polygons scene's step: 123 -> 102 us. Frictionless contacts
# are a convex problem, whose sweeps converge: they keep TOLERANCE alone.
STALL = 0.9
STALL_AFTER = 10
# The rest pass runs at most this many sweeps. It only ever takes kinetic energy out, and what a
# short pass leaves (a pressed contact still parting at a fraction of the rest speed) the next
# step's solve takes up; with friction it rarely meets TOLERANCE, and twenty sweeps cost as much
# as the whole velocity solve. Measured on the polygons scene's pile, four sweeps and twenty
# hold the same stacks and piles (tests/test_solver.py, test_polygon_engine.py).
REST_SWEEPS = 4

@compiled
def collide(rows, count, lin, ang, accelerations, inverse_masses, inverse_inertias, restitution, friction, rest_speed,
            dt, passes):
    """Impacts, on the velocities at the start of the step (lin (n, 2), ang (n,)) in place: see the
    module. Normal impulses add into rows.hit.

    A perfectly inelastic contact with a static still apart (restitution 0, gap > 0) that meets
    is no impact here but rows.arrives: an impulse now would stop the body where the step began,
    up to a step's travel short of the static (a box falling at 9.5 units/s stopped 0.26 above the
    floor at 30 fps and sank the rest over six frames). The solve, whose rows may close their gap
    and no more, brings it exactly onto the static by the step's end, and the rest pass stops it
    there. Between two bodies an impact still stops them where the step began: arriving there,
    the solve carried each landing down a column of tilted boxes, which rocked and spread by up
    to 0.061 instead of 0.049 (benchmarks/polygon_stacks.py)."""
    I, J, N, L, hit, arrives = rows.i, rows.j, rows.normal, rows.lever, rows.hit, rows.arrives
    partner, mass, mass_t = rows.partner, rows.mass, rows.mass_t
    hit[:count] = 0.0
    arrives[:count] = False
    slid = np.zeros(count)   # the friction impulse of each row's impacts
    for _ in range(passes):
        met = False
        r = 0
        while r < count:
            i, j, nx, ny = I[r], J[r], N[r, 0], N[r, 1]
            v, m = load(lin, ang, i, j), inverses(inverse_masses, inverse_inertias, i, j)
            closing = _impact(rows, r, v, accelerations, dt, rest_speed, restitution)
            if partner[r] == r + 1:
                s = r + 1
                other = _impact(rows, s, v, accelerations, dt, rest_speed, restitution)
                if closing < 0.0 and other < 0.0:
                    k11, k22, k12 = couplings(m, j, L[r, 0], L[r, 2], L[s, 0], L[s, 2])
                    possible, j1, j2 = together(k11, k22, k12, closing, other, restitution)
                    if possible:
                        v = kicked(v, m, j, nx, ny, L[r, 0], L[r, 1], L[r, 2], L[r, 3], j1, 0.0)
                        v = kicked(v, m, j, nx, ny, L[s, 0], L[s, 1], L[s, 2], L[s, 3], j2, 0.0)
                        hit[r] += j1
                        hit[s] += j2
                        if friction > 0.0:
                            for q in (r, s):
                                v, slid[q] = friction_kick(v, m, j, nx, ny, L[q, 0], L[q, 1], L[q, 2], L[q, 3],
                                                       mass_t[q], friction * hit[q], slid[q])
                        store(lin, ang, i, j, v)
                        met = True
                        r += 2
                        continue
            if closing < 0.0:
                impulse = newton_impulse(closing, restitution, mass[r])
                v = kicked(v, m, j, nx, ny, L[r, 0], L[r, 1], L[r, 2], L[r, 3], impulse, 0.0)
                hit[r] += impulse
                if friction > 0.0:
                    v, slid[r] = friction_kick(v, m, j, nx, ny, L[r, 0], L[r, 1], L[r, 2], L[r, 3], mass_t[r],
                                           friction * hit[r], slid[r])
                store(lin, ang, i, j, v)
                met = True
            r += 1
        if not met:
            return


@inlined
def _impact(rows, r, v, accelerations, dt, rest_speed, restitution):
    """Row r's closing speed if it is an impact collide takes (contact_row.meets), else 0; marks
    the row arriving instead where it meets a static perfectly inelastic and still apart."""
    i, j, L = rows.i[r], rows.j[r], rows.lever
    closing = meets(v, accelerations, i, j, rows.normal[r, 0], rows.normal[r, 1], L[r, 0], L[r, 2], rows.gap[r], dt,
                    rest_speed)
    if restitution == 0.0 and rows.gap[r] > 0.0 and j < 0:
        rows.arrives[r] = closing < 0.0   # (a later pass may find that another impact turned it)
        return 0.0
    return closing


@kernel
def _largest(impulses, count):
    largest = 0.0
    for r in range(count):
        largest = max(largest, impulses[r])
    return largest


@compiled
def _along_rows(rows, count, lin, ang, accelerations, dt, tangent):
    """Each row's relative mean velocity (count,) in the step (lin + ½·a·dt, ang: load_mean),
    along its normal, or along its tangent (-n_y, n_x) if `tangent`."""
    I, J, N, L = rows.i, rows.j, rows.normal, rows.lever
    out = np.empty(count)
    for r in range(count):
        v = load_mean(lin, ang, accelerations, dt, I[r], J[r])
        if tangent:
            out[r] = relative(v, J[r], -N[r, 1], N[r, 0], L[r, 1], L[r, 3])
        else:
            out[r] = relative(v, J[r], N[r, 0], N[r, 1], L[r, 0], L[r, 2])
    return out


@compiled
def solve_velocities(rows, count, lin, ang, accelerations, inverse_masses, inverse_inertias, friction, dt, iterations,
                     push_lin, push_ang, hold=True):
    """Steps 1 and 2, from the velocities (lin, ang): the contact impulses rows.impulse and
    rows.friction, and the change they make to each body's mean velocity, push_lin (n, 2) and
    push_ang (n,) (zeroed here for the rows' bodies, the only ones it sets; the mean velocity is
    lin + ½·a·dt + push). Returns the number of rows held from below (hold_from_below; hold None
    where nothing pulls: there is nothing to hold, and the hold is not compiled)."""
    zero_bodies(rows, count, push_lin, push_ang)
    # each row's relative velocity without contact impulses: the same in every sweep
    base = _along_rows(rows, count, lin, ang, accelerations, dt, False)
    base_t = _along_rows(rows, count, lin, ang, accelerations, dt, True)
    I, J, N, L, impulses, frictions = rows.i, rows.j, rows.normal, rows.lever, rows.impulse, rows.friction
    gap, partner, mass, mass_t = rows.gap, rows.partner, rows.mass, rows.mass_t
    for r in range(count):
        if impulses[r] != 0.0 or frictions[r] != 0.0:
            i, j = I[r], J[r]
            m = inverses(inverse_masses, inverse_inertias, i, j)
            v = kicked(load(push_lin, push_ang, i, j), m, j, N[r, 0], N[r, 1],
                       L[r, 0], L[r, 1], L[r, 2], L[r, 3], 0.5 * impulses[r], 0.5 * frictions[r])
            store(push_lin, push_ang, i, j, v)
    # what every sweep needs of a row and does not change: its target (its closing may not pass
    # its gap in the step), and a two-point manifold's couplings (on its first row), halved as an
    # impulse moves the mean velocity by half. Worked out in each sweep, they cost a fifth of it.
    target, pair_k = np.empty(count), np.empty((count, 3))
    for r in range(count):
        target[r] = -max(gap[r], 0.0) / dt
        if partner[r] == r + 1:
            m = inverses(inverse_masses, inverse_inertias, I[r], J[r])
            k11, k22, k12 = couplings(m, J[r], L[r, 0], L[r, 2], L[r + 1, 0], L[r + 1, 2])
            pair_k[r, 0], pair_k[r, 1], pair_k[r, 2] = 0.5 * k11, 0.5 * k22, 0.5 * k12
    scale = _largest(impulses, count)
    before = np.inf   # the change of the sweep before
    for sweep in range(iterations):
        change = 0.0   # the largest change of an accumulated impulse in this sweep
        for r in range(count):
            if friction > 0.0:   # friction first, within what the normal impulse allowed last sweep
                i, j, nx, ny = I[r], J[r], N[r, 0], N[r, 1]
                v = load(push_lin, push_ang, i, j)
                sliding = base_t[r] + relative(v, j, -ny, nx, L[r, 1], L[r, 3])
                limit = friction * impulses[r]
                spread = min(max(frictions[r] - 2.0 * mass_t[r] * sliding, -limit), limit)
                if spread != frictions[r]:
                    m = inverses(inverse_masses, inverse_inertias, i, j)
                    v = kicked(v, m, j, nx, ny, L[r, 0], L[r, 1], L[r, 2], L[r, 3],
                               0.0, 0.5 * (spread - frictions[r]))
                    store(push_lin, push_ang, i, j, v)
                    change = max(change, abs(spread - frictions[r]))
                    frictions[r] = spread
        r = 0
        while r < count:
            i, j, nx, ny = I[r], J[r], N[r, 0], N[r, 1]
            v, m = load(push_lin, push_ang, i, j), inverses(inverse_masses, inverse_inertias, i, j)
            closing = base[r] + relative(v, j, nx, ny, L[r, 0], L[r, 2])
            if partner[r] == r + 1:
                s = r + 1
                second = base[s] + relative(v, j, nx, ny, L[s, 0], L[s, 2])
                k11, k22, k12 = pair_k[r, 0], pair_k[r, 1], pair_k[r, 2]
                a1, a2 = impulses[r], impulses[s]
                found, x1, x2 = block(k11, k22, k12, closing - target[r] - (k11 * a1 + k12 * a2),
                                       second - target[s] - (k12 * a1 + k22 * a2))
                if found:
                    v = kicked(v, m, j, nx, ny, L[r, 0], L[r, 1], L[r, 2], L[r, 3], 0.5 * (x1 - a1), 0.0)
                    v = kicked(v, m, j, nx, ny, L[s, 0], L[s, 1], L[s, 2], L[s, 3], 0.5 * (x2 - a2), 0.0)
                    store(push_lin, push_ang, i, j, v)
                    impulses[r], impulses[s] = x1, x2
                    change, scale = max(change, abs(x1 - a1), abs(x2 - a2)), max(scale, x1, x2)
                    r += 2
                    continue
            total = max(impulses[r] + 2.0 * mass[r] * (target[r] - closing), 0.0)
            if total != impulses[r]:
                v = kicked(v, m, j, nx, ny, L[r, 0], L[r, 1], L[r, 2], L[r, 3], 0.5 * (total - impulses[r]), 0.0)
                store(push_lin, push_ang, i, j, v)
                change, scale = max(change, abs(total - impulses[r])), max(scale, total)
                impulses[r] = total
            r += 1
        if change <= TOLERANCE * scale or (friction > 0.0 and sweep + 1 >= STALL_AFTER and change > STALL * before):
            break
        before = change
    if hold is None:
        return 0
    # late: still closing faster than half a step of its bodies' pull (hold.py)
    return hold_from_below(rows, np.arange(count), target, base, 0.5 * dt, 0.0, accelerations, inverse_masses,
                           inverse_inertias, push_lin, push_ang, 0.5, impulses, base_t, friction)


@compiled
def solve_positions(rows, count, lin, ang, accelerations, inverse_masses, inverse_inertias, dt, iterations, push_lin,
                    push_ang, shift_lin, shift_ang, hold=True):
    """Step 3: pseudo-velocities shift_lin (n, 2), shift_ang (n,) (zeroed here for the rows'
    bodies, the only ones it sets) that take overlaps beyond the slop out at POSITION_RATE a step,
    given the solved mean velocities. Returns the number of rows held from below (hold: as in
    solve_velocities)."""
    zero_bodies(rows, count, shift_lin, shift_ang)
    rows.pseudo[:count] = 0.0
    I, J, N, L, pseudo = rows.i, rows.j, rows.normal, rows.lever, rows.pseudo
    gap, slop, mass = rows.gap, rows.slop, rows.mass
    over = np.flatnonzero(-gap[:count] - slop[:count] > 0.0)   # the rows with an overlap to take out
    if over.shape[0] == 0:
        return 0
    solved = np.empty(over.shape[0])   # each one's relative normal velocity after the solve
    goal = np.empty(over.shape[0])     # and the speed that takes out its share of the overlap
    for k in range(over.shape[0]):
        r = over[k]
        i, j, nx, ny = I[r], J[r], N[r, 0], N[r, 1]
        solved[k] = (relative(load_mean(lin, ang, accelerations, dt, i, j), j, nx, ny, L[r, 0], L[r, 2])
                     + relative(load(push_lin, push_ang, i, j), j, nx, ny, L[r, 0], L[r, 2]))
        goal[k] = POSITION_RATE * (-gap[r] - slop[r]) / dt
    scale = 0.0
    for _ in range(iterations):
        change = 0.0
        for k in range(over.shape[0]):
            r = over[k]
            i, j, nx, ny = I[r], J[r], N[r, 0], N[r, 1]
            v = load(shift_lin, shift_ang, i, j)
            closing = solved[k] + relative(v, j, nx, ny, L[r, 0], L[r, 2])
            total = max(pseudo[r] + mass[r] * (goal[k] - closing), 0.0)
            if total != pseudo[r]:
                m = inverses(inverse_masses, inverse_inertias, i, j)
                v = kicked(v, m, j, nx, ny, L[r, 0], L[r, 1], L[r, 2], L[r, 3],
                           total - pseudo[r], 0.0)
                store(shift_lin, shift_ang, i, j, v)
                change, scale = max(change, abs(total - pseudo[r])), max(scale, total)
                pseudo[r] = total
        if change <= TOLERANCE * scale:
            break
    if hold is None:
        return 0
    # a row held when less than half of its share of the overlap was taken out
    return hold_from_below(rows, over, goal, solved, 0.0, 0.5, accelerations, inverse_masses, inverse_inertias,
                           shift_lin, shift_ang, 1.0, pseudo, solved, 0.0)   # positions: no friction


@compiled
def come_to_rest(rows, count, lin, ang, inverse_masses, inverse_inertias, friction):
    """Step 4, on the final velocities (lin, ang) in place, in up to REST_SWEEPS sweeps: the rows
    that pressed leave at relative normal velocity 0 (their accumulated impulse may fall, never
    below 0), and friction takes out what sliding it can. Each correction takes one row's
    relative velocity toward 0, which only ever lowers kinetic energy: a resting contact does
    not bounce."""
    pressed, m = np.empty(count, np.int64), 0   # the rows that pressed (a loop: np.flatnonzero
    for r in range(count):                      # compiles numba's own, and its array expression)
        if rows.impulse[r] > 0.0:
            pressed[m] = r
            m += 1
    if m == 0:
        return
    pressed = pressed[:m]
    I, J, N, L, impulses, frictions = rows.i, rows.j, rows.normal, rows.lever, rows.impulse, rows.friction
    mass, mass_t = rows.mass, rows.mass_t
    scale = _largest(impulses, count)
    for _ in range(REST_SWEEPS):
        change = 0.0
        for r in pressed:
            i, j, nx, ny = I[r], J[r], N[r, 0], N[r, 1]
            v, m = load(lin, ang, i, j), inverses(inverse_masses, inverse_inertias, i, j)
            total = max(impulses[r] - mass[r] * relative(v, j, nx, ny, L[r, 0], L[r, 2]), 0.0)
            if total != impulses[r]:
                v = kicked(v, m, j, nx, ny, L[r, 0], L[r, 1], L[r, 2], L[r, 3], total - impulses[r], 0.0)
                change = max(change, abs(total - impulses[r]))
                impulses[r] = total
            if friction > 0.0:
                v, slid = friction_kick(v, m, j, nx, ny, L[r, 0], L[r, 1], L[r, 2], L[r, 3], mass_t[r], friction * total,
                                    frictions[r])
                change = max(change, abs(slid - frictions[r]))
                frictions[r] = slid
            store(lin, ang, i, j, v)
        if change <= TOLERANCE * scale:
            break


@kernel
def add_contact_motion(bodies, rows, count, push, push_turn, shift, shift_turn, dt, moved):
    """The solver's share of the step (response/solver.py): the contact impulses, spread over the
    step, move a body by push·dt and change its velocity by 2·push (and turn it likewise); the
    position correction moves it by shift·dt. In place, for the bodies of rows[:count] (the
    solver sets push and shift (n, 2) and their turns (n,) for those alone), each once: moved
    (n,) marks those done and is all False again on return. (The solver's passes over every
    body, this one, the clearing of push and shift and the mean velocities, took 14 ms of a
    200 ms step at a million bodies with a few thousand contacts.)"""
    for r in range(count):
        for i in (rows.i[r], rows.j[r]):
            if i >= 0 and not moved[i]:
                moved[i] = True
                _move_by_contacts(bodies, i, push, push_turn, shift, shift_turn, dt)
    for r in range(count):
        moved[rows.i[r]] = False
        if rows.j[r] >= 0:
            moved[rows.j[r]] = False


@inlined
def _move_by_contacts(bodies, i, push, push_turn, shift, shift_turn, dt):
    b = bodies
    for axis in range(2):
        b.positions[i, axis] += (push[i, axis] + shift[i, axis]) * dt
        b.velocities[i, axis] += 2.0 * push[i, axis]
    b.angles[i] += (push_turn[i] + shift_turn[i]) * dt
    b.angular_velocities[i] += 2.0 * push_turn[i]
