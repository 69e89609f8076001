"""The weight of sleeping bodies, carried down through the pile to the walls and segments.

A sleeping body (sleep.py) is frozen and has no events, but it still weighs: in a settled
pile the floor carries every body, not only the bottom layer resting on it. So each sleeper
keeps a load (Supports.load, an impulse vector): its weight times the time since it was last
carried, what the bodies resting on it passed to it, and the hits it took without waking.

At every frame time the loads go down the pile, from the highest sleeper to the lowest. Each
sleeper splits its load between the two of its supports whose normals lie nearest the load's
direction on either side of it — the walls, segments and lower sleeping bodies it touches
(within leaning.SLEEP_GAP of its radius) — by the same two-support statics as a body wedged on
two walls (support.py): N_a a + N_b b = -load. Only lower bodies support a sleeper, so loads
only go down and one pass from the top carries them all. A wall or a segment logs what it gets as a
kinds.SUPPORT event of the sleeper touching it; a sleeping body adds the reaction to its own
load, to pass on in turn. A body that wakes hands what it owes to its supports the same way,
at that instant, before it moves. So a still pile gives the floor its whole weight, m·g·dt
per body and frame, and its pressure on the side walls where it leans on them.

The vertical is exact: everything asleep weighs on the walls and segments under it, every
frame (the settled particles_250 gas under gravity: the floor carries its whole weight to
1e-13). The sideways pushes are one equilibrium among many: frictionless bodies side by side
may also press each other and the walls harder (statically indeterminate), and a sleeper
frozen off balance (a load no two of its supports enclose: it leans on a body at its own
height, or one still awake) hands its weight to the support that holds it up best, along
that support's normal, and its sideways imbalance to nobody. A sleeper with no support
asleep or fixed keeps its load until it has one (looked for again at every frame time: what
holds it up may be awake and move away), or wakes; one with nothing under it any more (no
floor or slope it touches, no body lower than itself: frozen leaning on a body that has since
moved away, and left beside a neighbour at its own height) wakes at the frame time and falls.
"""
import math

import numpy as np

from ...core.arrays import copy_rows, stable_order_of_floats
from ...broadphase.cells import reach_block, segment_range
from ...core.compiling import compiled, kernel
from ...core.geometry.box import wall_geometry
from ...core.geometry.segment import segment_contact
from ...core.kinds import N_WALLS, PAIR, SUPPORT
from ..eventlog import append, with_room
from .bodies import advance, wake
from .leaning import SLEEP_GAP, UPRIGHT, held_up
from .support import log_impulses

NONE = -1


@kernel
def take_hits(supports, contacts):
    """Add to each sleeper's load the impulse of the contacts of this instant that hit it
    without waking it (resolve.py: the awake body's contact, j = -1, pushing it along n)."""
    for k in range(contacts.count[0]):
        if contacts.kind[k] == PAIR and contacts.j[k] < 0:
            sleeper = contacts.other[k]
            supports.state[1] = 1
            supports.load[sleeper, 0] += contacts.impulse[k] * contacts.nx[k]
            supports.load[sleeper, 1] += contacts.impulse[k] * contacts.ny[k]


@kernel
def _owe_weight(bodies, env, supports, i, t):
    """Add particle i's weight since it was last carried to its load."""
    duration = t - supports.since[i]
    supports.load[i, 0] += bodies.mass[i] * env.gravity[0] * duration
    supports.load[i, 1] += bodies.mass[i] * env.gravity[1] * duration
    supports.since[i] = t


@kernel
def _enter(log, bodies, env, supports, i, t):
    """Particle i has fallen asleep: what its own supports gave it is logged up to t, and from
    t on its weight is carried as a load."""
    log_impulses(log, bodies, env, supports, i, t)
    supports.sleeping[i] = True


@kernel
def _nearer(angle, support, nx, ny, side, best):
    """Keep the support nearest the load's direction on one side: side +1 for angles >= 0
    (the smallest), -1 for angles <= 0 (the largest). best = (angle, support, nx, ny)."""
    if side * angle >= 0.0 and side * angle < side * best[0]:
        return angle, support, nx, ny
    return best


@kernel
def _fold(ux, uy, support, nx, ny, left, right):
    """Fold a support of normal n into the nearest on either side of direction u."""
    angle = math.atan2(ux * ny - uy * nx, ux * nx + uy * ny)
    return _nearer(angle, support, nx, ny, 1.0, left), _nearer(angle, support, nx, ny, -1.0, right)


@kernel
def _supports_of(bodies, grid, env, supports, i, ux, uy):
    """The supports of sleeper i nearest direction u on either side: two (angle, support,
    nx, ny), support a wall, N_WALLS + segment, or N_WALLS + segments + body (NONE: none)."""
    x, y, r = bodies.pos[i, 0], bodies.pos[i, 1], bodies.radius[i]
    left, right = (10.0, NONE, 0.0, 0.0), (-10.0, NONE, 0.0, 0.0)
    for wall in range(N_WALLS):
        axis, bound, inward = wall_geometry(env.box, wall, r)
        if abs((x, y)[axis] - bound) <= SLEEP_GAP * r:
            nx, ny = (inward, 0.0) if axis == 0 else (0.0, inward)
            left, right = _fold(ux, uy, wall, nx, ny, left, right)
    first, last, every = segment_range(grid, i, env.segments.shape[0])
    for k in range(first, last):
        segment = k if every else grid.segment_index[k]
        nx, ny, distance = segment_contact(x, y, env.segments[segment])[:3]
        if distance - r <= SLEEP_GAP * r:
            left, right = _fold(ux, uy, N_WALLS + segment, nx, ny, left, right)
    bodies_from = N_WALLS + env.segments.shape[0]
    cx_lo, cx_hi, cy_lo, cy_hi = reach_block(grid, grid.cell[i], grid.reach[i])
    width = cx_hi - cx_lo
    cells = width * (cy_hi - cy_lo)
    for slot in range(cells + grid.apart.shape[0]):   # the block's cells, then the bodies kept apart
        if slot < cells:
            j = grid.head[(cy_lo + slot // width) * grid.nx + cx_lo + slot % width]
        else:
            j = grid.apart[slot - cells]
        while j >= 0:
            dx, dy = x - bodies.pos[j, 0], y - bodies.pos[j, 1]
            distance = math.sqrt(dx * dx + dy * dy)
            # a sleeping body it touches, lower than it (against gravity): loads go downwards only
            if j != i and supports.sleeping[j] and distance > 0.0 and \
                    distance - r - bodies.radius[j] <= SLEEP_GAP * min(r, bodies.radius[j]) and \
                    dx * env.gravity[0] + dy * env.gravity[1] < 0.0:
                left, right = _fold(ux, uy, bodies_from + j, dx / distance, dy / distance, left, right)
            j = grid.next[j] if slot < cells else -1
    return left, right


@kernel
def _deliver(log, bodies, env, supports, i, t, support, nx, ny, push):
    """Support `support` pushes sleeper i along its normal n with impulse `push`: a wall or a
    segment logs it, a sleeping body takes the reaction into its load."""
    bodies_from = N_WALLS + env.segments.shape[0]
    if support < bodies_from and push > 0.0:
        r = bodies.radius[i]
        append(log, t, SUPPORT, i, support, push, bodies.pos[i, 0] - r * nx, bodies.pos[i, 1] - r * ny)
    elif support >= bodies_from:
        supports.load[support - bodies_from, 0] -= push * nx
        supports.load[support - bodies_from, 1] -= push * ny


@kernel
def _choose(bodies, grid, env, supports, i):
    """Which supports carry sleeper i's present load, and along which normals: (a, ax, ay, b,
    bx, by): two enclosing it (Cramer's rule), or b = NONE for a (its nearest) alone, or a = NONE
    for none at all."""
    fx, fy = -supports.load[i, 0], -supports.load[i, 1]   # what the supports must push with
    force = math.sqrt(fx * fx + fy * fy)
    if force == 0.0:
        return NONE, 0.0, 0.0, NONE, 0.0, 0.0
    left, right = _supports_of(bodies, grid, env, supports, i, fx / force, fy / force)
    a, b = right, left
    if a[1] != NONE and b[1] != NONE and b[0] - a[0] < math.pi and min(-a[0], b[0]) > UPRIGHT:
        return a[1], a[2], a[3], b[1], b[2], b[3]
    # Not enclosed (a body frozen off balance, or upright on one support): the one that holds it
    # up best carries its weight, the part of the load along gravity, whole (_split)
    gx, gy = env.gravity[0], env.gravity[1]
    up_a = -(a[2] * gx + a[3] * gy) if a[1] != NONE else 0.0
    up_b = -(b[2] * gx + b[3] * gy) if b[1] != NONE else 0.0
    if max(up_a, up_b) <= 0.0:
        return NONE, 0.0, 0.0, NONE, 0.0, 0.0
    best = a if up_a >= up_b else b
    return best[1], best[2], best[3], NONE, 0.0, 0.0


@kernel
def _split(log, bodies, env, supports, i, t, a, ax, ay, b, bx, by):
    """Pass sleeper i's load on to supports a and b (as _choose gives them); its load is then 0,
    or kept whole if it has no support."""
    if a == NONE:
        return
    fx, fy = -supports.load[i, 0], -supports.load[i, 1]
    supports.load[i, 0] = supports.load[i, 1] = 0.0
    if b == NONE:   # along a's normal, as much as holds the load's part along gravity
        gx, gy = env.gravity[0], env.gravity[1]
        _deliver(log, bodies, env, supports, i, t, a, ax, ay, (fx * gx + fy * gy) / (ax * gx + ay * gy))
        return
    determinant = ax * by - ay * bx   # N_a a + N_b b = f: Cramer's rule
    _deliver(log, bodies, env, supports, i, t, a, ax, ay, (fx * by - fy * bx) / determinant)
    _deliver(log, bodies, env, supports, i, t, b, bx, by, (ax * fy - ay * fx) / determinant)


@kernel
def pass_on(log, bodies, grid, env, supports, i, t):
    """Split sleeper i's load between its supports (module docstring). The caller makes room
    for 2 events."""
    a, ax, ay, b, bx, by = _choose(bodies, grid, env, supports, i)
    _split(log, bodies, env, supports, i, t, a, ax, ay, b, bx, by)
@kernel
def note_sleepers(log, bodies, grid, env, supports, particles, count, t):
    """After an event at t involving particles[:count]: those that fell asleep start being
    carried; those woken hand what they owe to their supports, the highest first (wake_up lists
    them upwards), while still where they slept. The caller makes room for 2 count events."""
    for k in range(count - 1, -1, -1):
        i = particles[k]
        if supports.sleeping[i] and not bodies.asleep[i]:
            supports.state[1] = 1   # the loads change: carry_sleepers chooses the supports again
            _owe_weight(bodies, env, supports, i, t)
            pass_on(log, bodies, grid, env, supports, i, t)
            supports.load[i, 0] = supports.load[i, 1] = 0.0
            supports.sleeping[i] = False
    for k in range(count):
        i = particles[k]
        if bodies.asleep[i] and not supports.sleeping[i]:
            supports.state[1] = 1
            _enter(log, bodies, env, supports, i, t)


@compiled(error_model="numpy")
def carry_sleepers(log, bodies, grid, env, supports, t, woken, count_woken):
    """At a frame time: every sleeper's weight since last carried joins its load, and the loads
    go down the pile, highest sleeper first. A sleeper with nothing under it any more (it fell
    asleep leaning on a body that has since moved away) wakes, to fall: it is added to
    woken[count_woken:] for the caller to predict. Returns the log (with room made)
    and the new count of woken.

    Which supports carry each sleeper is kept (Supports.plan): while no body falls asleep or
    wakes and no sleeper is hit, every load is its weight times the frame's duration plus the
    same shares of the same loads above, so the choice is the same and only the arithmetic is
    redone — a settled pile costs a few operations per body and frame."""
    state, order = supports.state, supports.order
    replay = state[1] == 0 and state[2] == 1
    count = state[0]
    if not replay:
        count = 0
        for i in range(bodies.radius.shape[0]):
            count += bodies.asleep[i]
    log = with_room(log, 4 * count)
    if replay:
        for k in range(count):
            _owe_weight(bodies, env, supports, order[k], t)
        for k in range(count):
            i = order[k]
            _split(log, bodies, env, supports, i, t, supports.plan[i, 0], supports.normal[i, 0], supports.normal[i, 1],
                   supports.plan[i, 1], supports.normal[i, 2], supports.normal[i, 3])
        return log, count_woken
    height = np.empty(count)
    count, entered = 0, False
    for i in range(bodies.radius.shape[0]):
        if bodies.asleep[i]:
            if not supports.sleeping[i]:   # fell asleep at this frame time, or by the budget's fallback
                _enter(log, bodies, env, supports, i, t)
                entered = True
            _owe_weight(bodies, env, supports, i, t)
            order[count] = i
            height[count] = bodies.pos[i, 0] * env.gravity[0] + bodies.pos[i, 1] * env.gravity[1]   # -height
            count += 1
    copy_rows(order[:count][stable_order_of_floats(height)], order, count)   # highest first (arrays.py)
    for k in range(count):
        i = order[k]
        loaded = supports.load[i, 0] != 0.0 or supports.load[i, 1] != 0.0   # (not: asleep from just now)
        a, ax, ay, b, bx, by = _choose(bodies, grid, env, supports, i)
        if a == NONE and loaded and not held_up(bodies, grid, env, i, t):   # nothing under it: it falls
            advance(bodies, i, t)
            wake(bodies, env, i)
            supports.sleeping[i] = False
            supports.load[i, 0] = supports.load[i, 1] = 0.0
            woken[count_woken] = i
            count_woken += 1
            entered = True   # the set of sleepers changes: choose again next frame
        elif a == NONE and loaded:
            entered = True   # held up by awake bodies only: look again next frame, they may move away
        supports.plan[i, 0], supports.plan[i, 1] = a, b
        supports.normal[i, 0], supports.normal[i, 1], supports.normal[i, 2], supports.normal[i, 3] = ax, ay, bx, by
        _split(log, bodies, env, supports, i, t, a, ax, ay, b, bx, by)
    # the plan holds for the next frames if these loads were weights alone, over the whole frame
    state[0], state[2], state[1] = count, state[1] == 0 and not entered, 0
    return log, count_woken
